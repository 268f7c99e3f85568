//! The classical baselines: greedy insertion (Garland & Heckbert 1995) and edge decimation
//! (after Schroeder et al. 1992).
