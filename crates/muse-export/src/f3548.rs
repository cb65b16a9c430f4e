//! Flights as ASTM F3548-21 operational intents.
