//! Small dense linear algebra for the constant matrices schemes precompute once (energy
//! minimisers, projections). Sizes are tens of rows, so plain Gauss–Jordan is the right tool;
//! nothing here runs per face.

/// A dense row-major matrix.
pub(crate) type Matrix = Vec<Vec<f64>>;

/// Inverse of a square matrix by Gauss–Jordan elimination with partial pivoting. Returns `None`
/// when a pivot falls below `1e-12` times the largest entry (numerically singular).
pub(crate) fn invert(a: &Matrix) -> Option<Matrix> {
    let n = a.len();
    let scale = a
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    let mut work: Matrix = a.clone();
    let mut inv: Matrix = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| work[x][col].abs().total_cmp(&work[y][col].abs()))?;
        if work[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        work.swap(col, pivot);
        inv.swap(col, pivot);
        let p = work[col][col];
        for j in 0..n {
            work[col][j] /= p;
            inv[col][j] /= p;
        }
        let (pivot_work, pivot_inv) = (work[col].clone(), inv[col].clone());
        for r in (0..n).filter(|&r| r != col) {
            let f = work[r][col];
            if f != 0.0 {
                for j in 0..n {
                    work[r][j] -= f * pivot_work[j];
                    inv[r][j] -= f * pivot_inv[j];
                }
            }
        }
    }
    Some(inv)
}

/// `a · b`.
pub(crate) fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    let inner = b.len();
    a.iter()
        .map(|row| {
            (0..b.first().map_or(0, Vec::len))
                .map(|j| (0..inner).map(|k| row[k] * b[k][j]).sum())
                .collect()
        })
        .collect()
}

/// `aᵀ`.
pub(crate) fn transpose(a: &Matrix) -> Matrix {
    (0..a.first().map_or(0, Vec::len))
        .map(|j| a.iter().map(|row| row[j]).collect())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_times_matrix_is_identity() {
        let a: Matrix = (0..7)
            .map(|i| {
                (0..7)
                    .map(|j| 1.0 / (1.0 + (i + 2 * j) as f64) + f64::from(u8::from(i == j)))
                    .collect()
            })
            .collect();
        let inv = invert(&a).expect("regular");
        let id = multiply(&a, &inv);
        for (i, row) in id.iter().enumerate() {
            for (j, x) in row.iter().enumerate() {
                let expected = f64::from(u8::from(i == j));
                assert!((x - expected).abs() < 1e-12, "({i},{j}) = {x}");
            }
        }
        assert_eq!(transpose(&transpose(&a)), a);
    }

    #[test]
    fn singular_matrix_has_no_inverse() {
        let a = vec![vec![1.0, 2.0], vec![2.0, 4.0]];
        assert!(invert(&a).is_none());
    }
}
