//! The optimiser's test binary: random small batches (`instances`) on which every optimised
//! schedule passes the independent verifier, is never worse than first come, first served and
//! repeats exactly (`valid`); the best schedule over every planning order, found by
//! exhaustion (`orders`), and the true optimum over every valid schedule, found by
//! conflict-based search (`optimum`), against which the optimiser is measured
//! (`against_optimum`).

mod against_optimum;
mod instances;
mod optimum;
mod orders;
mod valid;
