//! Optimizers over genform genomes.
#![warn(missing_docs)]
