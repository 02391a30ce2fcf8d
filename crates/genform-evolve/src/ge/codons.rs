//! The genome of grammatical evolution: a string of codons ([`Codons`]).
//! Kept apart from the optimizer so the operators and both codon
//! optimizers can name it without importing one another.

/// A codon string: the genome of grammatical evolution. Codons lie in
/// `0..codon_range` of the optimizer's configuration.
pub type Codons = Vec<u32>;
