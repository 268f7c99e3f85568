//! The evolutionary algorithms and their operators: NSGA-II, orthogonal-array crossover, the
//! weighted-sum GA.
