//! Mean and standard deviation of a sample, honest about samples of one.

use serde::Serialize;

/// The mean and sample standard deviation of some values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Number of values.
    pub n: usize,
    /// Their mean.
    pub mean: f64,
    /// The sample standard deviation (denominator n − 1); `None` for a single value, where it
    /// is undefined (a deterministic method run once has no spread to estimate).
    pub std: Option<f64>,
}

impl Summary {
    /// Summarises `values`; `None` if there are none.
    ///
    /// ```
    /// use paretomesh::experiment::Summary;
    /// let s = Summary::of(&[1.0, 2.0, 3.0]).unwrap();
    /// assert_eq!((s.n, s.mean, s.std), (3, 2.0, Some(1.0)));
    /// assert_eq!(Summary::of(&[5.0]).unwrap().std, None);
    /// ```
    pub fn of(values: &[f64]) -> Option<Summary> {
        let n = values.len();
        if n == 0 {
            return None;
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        let std = (n > 1).then(|| {
            let squares: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
            (squares / (n - 1) as f64).sqrt()
        });
        Some(Summary { n, mean, std })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_standard_deviation_uses_n_minus_one() {
        // Values 2, 4, 4, 4, 5, 5, 7, 9: mean 5, squares sum 32, 32 / 7.
        let s = Summary::of(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]).unwrap();
        assert_eq!(s.mean, 5.0);
        assert!((s.std.unwrap() - (32.0f64 / 7.0).sqrt()).abs() < 1e-15);
        assert_eq!(Summary::of(&[]), None);
    }
}
