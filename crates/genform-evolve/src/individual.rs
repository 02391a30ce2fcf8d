//! A genome with its cached fitness ([`Individual`]), and what statistics
//! need to know about a genome representation ([`Genotype`]). Kept apart
//! from the [`Optimizer`](crate::optimizer::Optimizer) trait so the
//! statistics the trait returns can read individuals without importing it.

use genform_core::Genome;

/// What statistics need to know about a genome representation.
pub trait Genotype {
    /// Its length: genes of a [`Genome`], codons of a codon string.
    fn length(&self) -> usize;
}

impl Genotype for Genome {
    fn length(&self) -> usize {
        self.len()
    }
}

impl Genotype for Vec<u32> {
    fn length(&self) -> usize {
        self.len()
    }
}

/// A genome with its cached fitness.
#[derive(Clone, Debug, PartialEq)]
pub struct Individual<G = Genome> {
    /// The genome.
    pub genome: G,
    /// Its fitness; non-finite means invalid (see [`Objective`](crate::objective::Objective)).
    pub fitness: f64,
}

impl<G> Individual<G> {
    /// Whether the fitness is finite.
    pub fn is_valid(&self) -> bool {
        self.fitness.is_finite()
    }
}
