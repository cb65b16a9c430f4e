//! The SQLite store's tables, as created in a new store (of the format `meta::FORMAT` names).
//!
//! Times are milliseconds since the Unix epoch (UTC) in columns named `…_ms`; plans are JSON
//! arrays of `[node id, arrive ms, depart ms]` stays. Every table carries `crc`, the CRC-32 of
//! the row's other columns (see `rows`), checked whenever the service reads the row.

/// The database's page size, bytes. Every commit writes each page it changed to the WAL in
/// full; a commit changes a few pages per table and index (the rows it appends, the index
/// entries it adds), so small pages keep the bytes written per answer small.
pub const PAGE_SIZE: u32 = 1024;

/// The count of write transactions and the store's identity (see `acked`): one row, raised by
/// every transaction. Created in a new store, and added to a store written before it.
pub const CREATE_COMMITS: &str = "
CREATE TABLE commits (
    one   INTEGER PRIMARY KEY CHECK (one = 1),
    store INTEGER NOT NULL,              -- a random number naming this store (ACKED names it too)
    n     INTEGER NOT NULL,              -- write transactions committed
    crc   INTEGER NOT NULL
);
";

/// Creates every table, index and view of a new store (and [`CREATE_COMMITS`]'s, after it).
pub const CREATE: &str = "
CREATE TABLE meta (
    key   TEXT PRIMARY KEY,
    value TEXT NOT NULL,
    crc   INTEGER NOT NULL
) WITHOUT ROWID;

-- One row per request ever answered, for the life of the store: the request, the first
-- answer, and the flight's current state.
CREATE TABLE flights (
    seq            INTEGER PRIMARY KEY,  -- the service's sequence number (answer order)
    id             TEXT NOT NULL UNIQUE, -- the client's id: names this flight forever
    operator       TEXT NOT NULL,
    origin         TEXT NOT NULL,
    destination    TEXT NOT NULL,
    departure_ms   INTEGER NOT NULL,     -- requested departure
    answered_ms    INTEGER NOT NULL,
    plan           TEXT,                 -- the first plan, when planned
    reason         TEXT,                 -- the rejection reason, when rejected
    free_flow_ms   INTEGER,
    expanded       INTEGER NOT NULL,     -- search labels expanded
    status         TEXT NOT NULL,        -- planned, rejected, cancelled, replanned, diverted, contingency
    takeoff_ms     INTEGER NOT NULL,     -- take-off of the current plan (the departure if none)
    landing_ms     INTEGER NOT NULL,     -- landing of the current plan (the departure if none)
    holds_until_ms INTEGER,              -- last instant it holds a reservation (NULL: none)
    cancelled_ms   INTEGER,              -- when its operator cancelled it
    changes        TEXT,                 -- zone changes: [{zone, announced_ms, airborne, outcome, plan}]
    crc            INTEGER NOT NULL
);
CREATE INDEX flights_by_operator ON flights (operator, seq);
CREATE INDEX flights_holding ON flights (holds_until_ms) WHERE holds_until_ms IS NOT NULL;

-- Zones announced during the day (docs/reference.md#zones-announced-during-the-day), in announcement order.
CREATE TABLE zones (
    seq          INTEGER PRIMARY KEY,
    id           TEXT NOT NULL UNIQUE,
    feature      TEXT NOT NULL,          -- the ED-318 feature as received
    announced_ms INTEGER NOT NULL,
    withdrawn_ms INTEGER,
    affected     INTEGER NOT NULL,       -- flights it changed
    crc          INTEGER NOT NULL
);

-- Every change of a flight, in the order decided: the event stream of GET /v1/events.
CREATE TABLE events (
    id         INTEGER PRIMARY KEY,
    at_ms      INTEGER NOT NULL,
    kind       TEXT NOT NULL,            -- planned, cancelled, replanned, diverted, contingency
    flight_seq INTEGER NOT NULL REFERENCES flights (seq),
    zone       TEXT,                     -- the zone announcement that caused it
    changes    INTEGER NOT NULL,         -- zone changes the flight had just after it
    crc        INTEGER NOT NULL
);

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
