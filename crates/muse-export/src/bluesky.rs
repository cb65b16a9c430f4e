//! A day of flights as a BlueSky scenario file.
