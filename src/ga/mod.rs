//! Genetic algorithm over grading and packing-rule genes (to come; the packer
//! is its fitness kernel and knows nothing of it).
