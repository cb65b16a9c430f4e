//! The PostgreSQL store's tables: the SQLite store's columns (see `sqlite::schema`), with
//! PostgreSQL's types (`bigint` for SQLite's integers), made in the connection's schema (the
//! first of its `search_path`, `public` by default) at the first start.

/// Creates every table, index and view of a new store.
pub(super) const CREATE: &str = "
CREATE TABLE meta (
    key   text PRIMARY KEY,
    value text NOT NULL,
    crc   bigint NOT NULL
);

-- One row per request ever answered, for the life of the store: the request, the first
-- answer, and the flight's current state.
CREATE TABLE flights (
    seq            bigint PRIMARY KEY,   -- the service's sequence number (answer order)
    id             text NOT NULL UNIQUE, -- the client's id: names this flight forever
    operator       text NOT NULL,
    origin         text NOT NULL,
    destination    text NOT NULL,
    departure_ms   bigint NOT NULL,      -- requested departure
    answered_ms    bigint NOT NULL,
    plan           text,                 -- the first plan, when planned
    reason         text,                 -- the rejection reason, when rejected
    free_flow_ms   bigint,
    expanded       bigint NOT NULL,      -- search labels expanded
    status         text NOT NULL,        -- planned, rejected, cancelled, replanned, diverted, contingency
    takeoff_ms     bigint NOT NULL,      -- take-off of the current plan (the departure if none)
    landing_ms     bigint NOT NULL,      -- landing of the current plan (the departure if none)
    holds_until_ms bigint,               -- last instant it holds a reservation (NULL: none)
    cancelled_ms   bigint,               -- when its operator cancelled it
    changes        text,                 -- zone changes: [{zone, announced_ms, airborne, outcome, plan}]
    crc            bigint NOT NULL
);
CREATE INDEX flights_by_operator ON flights (operator, seq);
CREATE INDEX flights_holding ON flights (holds_until_ms) WHERE holds_until_ms IS NOT NULL;

-- Zones announced during the day, in announcement order.
CREATE TABLE zones (
    seq          bigint PRIMARY KEY,
    id           text NOT NULL UNIQUE,
    feature      text NOT NULL,          -- the ED-318 feature as received
    announced_ms bigint NOT NULL,
    withdrawn_ms bigint,
    affected     bigint NOT NULL,        -- flights it changed
    crc          bigint NOT NULL
);

-- Every change of a flight, in the order decided: the event stream of GET /v1/events.
CREATE TABLE events (
    id         bigint PRIMARY KEY,
    at_ms      bigint NOT NULL,
    kind       text NOT NULL,            -- planned, cancelled, replanned, diverted, contingency
    flight_seq bigint NOT NULL REFERENCES flights (seq),
    zone       text,                     -- the zone announcement that caused it
    changes    bigint NOT NULL,          -- zone changes the flight had just after it
    crc        bigint NOT NULL
);
CREATE INDEX events_by_flight ON events (flight_seq);

-- Convenience views for people querying the store with their own tools.
CREATE VIEW cancellations AS
    SELECT f.id AS flight, f.operator, e.at_ms, e.id AS event
    FROM events e JOIN flights f ON f.seq = e.flight_seq
    WHERE e.kind = 'cancelled' AND e.zone IS NULL;
CREATE VIEW zone_outcomes AS
    SELECT e.zone, f.id AS flight, f.operator, e.kind AS outcome, e.at_ms, e.id AS event
    FROM events e JOIN flights f ON f.seq = e.flight_seq
    WHERE e.zone IS NOT NULL;
";

/// The lease: which service leads the store (see `lease`). One row, made by the first service
/// that leads; made too in a store written before it.
pub(super) const CREATE_LEASE: &str = "
CREATE TABLE IF NOT EXISTS lease (
    one      integer PRIMARY KEY CHECK (one = 1),
    term     bigint NOT NULL,              -- raised by one at every change of leader
    holder   text NOT NULL,                -- the leader's address, as it advertised it
    since_ms bigint NOT NULL               -- when it took the lead
);
";
