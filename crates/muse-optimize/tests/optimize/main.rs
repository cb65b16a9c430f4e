//! The optimiser's test binary: random small batches (`instances`) on which every optimised
//! schedule passes the independent verifier, is never worse than first come, first served and
//! repeats exactly (`valid`), and the best schedule over every planning order, found by
//! exhaustion, against which the optimiser is measured (`orders`).

mod instances;
mod orders;
mod valid;
