//! Indicators and statistics for comparing fronts: hypervolume, epsilon, coverage, Wilcoxon
//! rank-sum, and the paper's trade-off pick.
