//! Across the sections (`v`): the parameters of the sections and the curves through or near
//! the columns of their control points.

use super::compatible::{least_score, placements, residual, smoothing_lambda, LSQ_ENERGY_WEIGHT};
use crate::curve::to_homogeneous;
use crate::fit::constrained::EnergyGram;
use crate::fit::interp::InterpolationSolver;
use crate::fit::knots::{knots_for_approximation, knots_for_interpolation};
use crate::fit::lsq::LeastSquaresSolver;
use crate::fit::param::{chord_lengths, uniform_params, universal_params};
use crate::fit::Parameterization;
use crate::tolerance::COINCIDENT_REL;
use crate::{KnotVector, NurbsError, Vec3};

/// Parameters across the sections: for [`Parameterization::Universal`] the universal values for
/// `K` points; otherwise, as The NURBS Book A9.4 / eq. 10.8, the mean over the columns
/// `col(i) = (X_{i,0}, ..., X_{i,K-1})` of each column's own parameters (eq. 9.3-9.6), skipping
/// columns whose points all coincide. Both skins pass the columns of the sections' control
/// points (the curves that are then fitted across), not of the data.
///
/// # Errors
/// [`NurbsError::CoincidentPoints`] if two consecutive sections coincide in every column.
pub(super) fn cross_params(
    n_cols: usize,
    k_sections: usize,
    column: impl Fn(usize, usize) -> Vec3,
    kind: Parameterization,
    degree_v: usize,
) -> Result<Vec<f64>, NurbsError> {
    let v = match kind {
        Parameterization::Universal => return universal_params(k_sections, degree_v, "sections"),
        Parameterization::Uniform => uniform_params(k_sections),
        Parameterization::ChordLength | Parameterization::Centripetal => {
            let mut sum = vec![0.0; k_sections];
            let mut used = 0usize;
            let mut pts = Vec::with_capacity(k_sections);
            for i in 0..n_cols {
                pts.clear();
                pts.extend((0..k_sections).map(|k| column(i, k)));
                let mut d = chord_lengths(&pts);
                if kind == Parameterization::Centripetal {
                    d.iter_mut().for_each(|x| *x = x.sqrt());
                }
                let total: f64 = d.iter().sum();
                if total <= 0.0 {
                    continue;
                }
                used += 1;
                let mut acc = 0.0;
                for (s, dk) in sum[1..].iter_mut().zip(&d) {
                    acc += dk;
                    *s += acc / total;
                }
            }
            if used == 0 {
                return Err(NurbsError::CoincidentPoints { what: "sections (all of them)".into(), index: 0, next: 1 });
            }
            let mut v: Vec<f64> = sum.iter().map(|s| s / used as f64).collect();
            v[0] = 0.0;
            v[k_sections - 1] = 1.0;
            v
        }
    };
    // A gap below COINCIDENT_REL in every column means two sections in the same place.
    if let Some(index) = v.windows(2).position(|w| w[1] - w[0] <= COINCIDENT_REL) {
        return Err(NurbsError::CoincidentPoints { what: "sections".into(), index, next: index + 1 });
    }
    Ok(v)
}

/// Interpolate every column `columns[i] = (R_{i,0}, ..., R_{i,K-1})` across the sections with one
/// factorization and assemble the u-major net.
pub(super) fn interpolate_across(
    rows: &[Vec<Vec3>],
    v: &[f64],
    kind: Parameterization,
    q: usize,
) -> Result<(KnotVector, Vec<[f64; 4]>), NurbsError> {
    let kv = knots_for_interpolation(v, q, kind)?;
    let solver = InterpolationSolver::new(v, &kv)?;
    let n_u = rows[0].len();
    let mut net = Vec::with_capacity(n_u * v.len());
    let mut col: Vec<[f64; 3]> = vec![[0.0; 3]; v.len()];
    for i in 0..n_u {
        for (c, row) in col.iter_mut().zip(rows) {
            *c = row[i].to_array();
        }
        solver.solve_in_place(&mut col)?;
        net.extend(col.iter().map(|&c| to_homogeneous(Vec3::from_array(c), 1.0)));
    }
    Ok((kv, net))
}

/// Step 2 of [`skin_approximate`]: the `v` knots, the u-major net and the v-parameters.
pub(super) struct AcrossFit {
    pub(super) knots: KnotVector,
    pub(super) net: Vec<[f64; 4]>,
    pub(super) v: Vec<f64>,
}

/// Fit the columns of the rows' control points across the sections for each placement and
/// keep the one with the least `sum over columns of (residual + λ E)` (step 2).
pub(super) fn fit_across(
    rows: &[Vec<Vec3>],
    nv: usize,
    q: usize,
    kind: Parameterization,
    smoothing: f64,
) -> Result<AcrossFit, NurbsError> {
    let (nu, k_count) = (rows[0].len(), rows.len());
    let v = cross_params(nu, k_count, |i, k| rows[k][i], kind, q)?;
    let columns: Vec<Vec<Vec3>> = (0..nu).map(|i| rows.iter().map(|r| r[i]).collect()).collect();
    let fits = placements(kind).iter().map(|&placement| {
        match placement {
            Some(pl) => pl.knots(&v, nv, q),
            None => knots_for_approximation(&v, nv, q, kind),
        }
        .and_then(|kv| {
            let gram = EnergyGram::new(&kv);
            let smooth = smoothing_lambda(&gram, v.len(), smoothing);
            let solver = LeastSquaresSolver::smoothing(&v, &kv, smooth)?;
            let lambda = LSQ_ENERGY_WEIGHT / gram.max_diagonal() + smooth;
            let mut score = 0.0;
            let mut cps = Vec::with_capacity(nu);
            for col in &columns {
                let cp = solver.control_points(col)?;
                score += residual(&kv, &v, col, &cp) + lambda * gram.energy(&cp);
                cps.push(cp);
            }
            Ok((score, (kv, cps)))
        })
    });
    let (_, (knots, cps)) = least_score(fits, "placements()")?;
    let net = cps.iter().flatten().map(|&c| to_homogeneous(c, 1.0)).collect();
    Ok(AcrossFit { knots, net, v })
}
