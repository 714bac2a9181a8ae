//! Joining drawn pieces into runs, before they are sorted into stations.
//!
//! A station may be drawn in pieces (a `LINE` for the flat of bottom, an `ARC` for the bilge,
//! a `LINE` up the side). Two pieces are joined where an end of one meets an end of the other
//! and no third end is there: several stations often start at one keel point, where nothing is
//! joined. Nor are two ends where the path would turn back by more than 150° (a cusp): that
//! is two stations meeting head on, e.g. at a common deck edge in a parallel middle body.
//! Before the pieces are sorted into stations (by label or by order) ends on the centreline
//! are not joined either, since every station may start there; within a layer or a
//! label, which is one station, they are. A station's curves that stay apart are put one above
//! the other (they must not overlap in height), each from its lower end up.

use super::geom::P2;

/// `cos 30°`: pieces whose joint would turn the path by more than 150° are not joined.
const CUSP_COS: f64 = 0.866_025_403_784_438_6;

/// A run of joined pieces: its points and, per point, the index of the curve it came from.
#[derive(Clone, Debug)]
pub(super) struct Chain {
    pub(super) pts: Vec<P2>,
    pub(super) src: Vec<usize>,
}

impl Chain {
    pub(super) fn first_curve(&self) -> usize {
        self.src.iter().copied().min().unwrap_or(0)
    }
    pub(super) fn curves(&self) -> Vec<usize> {
        let mut c = self.src.clone();
        c.sort_unstable();
        c.dedup();
        c
    }
}

/// Join chains end to end where exactly two ends meet within `tol` (see the module docs);
/// ends within `tol` of `x = cl` are left alone unless `cl` is `None`. Chains that close on
/// themselves are returned in `loops`.
pub(super) fn join(chains: Vec<Chain>, tol: f64, cl: Option<f64>) -> (Vec<Chain>, Vec<Chain>) {
    let n = chains.len();
    let end = |e: usize| {
        let c = &chains[e / 2];
        if e.is_multiple_of(2) {
            c.pts[0]
        } else {
            c.pts[c.pts.len() - 1]
        }
    };
    // Candidates of each end: the ends of other chains within tol (sweep along x).
    let mut order: Vec<usize> = (0..2 * n).collect();
    order.sort_by(|&a, &b| end(a)[0].total_cmp(&end(b)[0]));
    let mut cand: Vec<Vec<usize>> = vec![Vec::new(); 2 * n];
    for (k, &a) in order.iter().enumerate() {
        let pa = end(a);
        for &b in &order[k + 1..] {
            let pb = end(b);
            if pb[0] - pa[0] > tol {
                break;
            }
            if a / 2 != b / 2 && (pa[0] - pb[0]).hypot(pa[1] - pb[1]) <= tol {
                cand[a].push(b);
                cand[b].push(a);
            }
        }
    }
    let on_cl = |e: usize| cl.is_some_and(|x0| (end(e)[0] - x0).abs() <= tol);
    // The direction along the chain into end e (from its neighbouring point).
    let into = |e: usize| {
        let p = &chains[e / 2].pts;
        let (a, b) = if e.is_multiple_of(2) { (p[1], p[0]) } else { (p[p.len() - 2], p[p.len() - 1]) };
        [b[0] - a[0], b[1] - a[1]]
    };
    // Joining e to f turns the path from into(e) to -into(f); a turn of more than 150 degrees
    // is a cusp: two curves meeting head on (two stations ending at one deck point), not the
    // pieces of one.
    let cusp = |e: usize, f: usize| {
        let (a, b) = (into(e), into(f));
        let (na, nb) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
        na > 0.0 && nb > 0.0 && -(a[0] * b[0] + a[1] * b[1]) / (na * nb) < -CUSP_COS
    };
    let link: Vec<Option<usize>> = (0..2 * n)
        .map(|e| match cand[e][..] {
            [f] if cand[f][..] == [e] && !on_cl(e) && !on_cl(f) && !cusp(e, f) => Some(f),
            _ => None,
        })
        .collect();
    let mut used = vec![false; n];
    let mut out = Vec::new();
    let walk = |start_end: usize, used: &mut Vec<bool>| {
        let mut chain = Chain { pts: Vec::new(), src: Vec::new() };
        let mut e_in = start_end;
        loop {
            let i = e_in / 2;
            if used[i] {
                break;
            }
            used[i] = true;
            let c = &chains[i];
            let idx: Vec<usize> =
                if e_in.is_multiple_of(2) { (0..c.pts.len()).collect() } else { (0..c.pts.len()).rev().collect() };
            let skip = usize::from(!chain.pts.is_empty());
            for &k in &idx[skip..] {
                chain.pts.push(c.pts[k]);
                chain.src.push(c.src[k]);
            }
            match link[e_in ^ 1] {
                Some(f) => e_in = f,
                None => break,
            }
        }
        chain
    };
    // Open runs start at an end without a link.
    for e in 0..2 * n {
        if !used[e / 2] && link[e].is_none() {
            out.push(walk(e, &mut used));
        }
    }
    // What is left is closed.
    let mut loops = Vec::new();
    for i in 0..n {
        if !used[i] {
            loops.push(walk(2 * i, &mut used));
        }
    }
    (out, loops)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(pts: &[P2], id: usize) -> Chain {
        Chain { pts: pts.to_vec(), src: vec![id; pts.len()] }
    }

    /// Three pieces of one curve, shuffled and reversed, join into one run; two runs that
    /// start at one centreline point stay apart when the centreline is guarded, and a third
    /// end at a point blocks joining there.
    #[test]
    fn joining_pieces() {
        let a = chain(&[[0.0, 0.0], [1.0, 0.0]], 0);
        let b = chain(&[[2.0, 1.0], [1.0, 0.0]], 1);
        let c = chain(&[[2.0, 1.0], [2.0, 3.0]], 2);
        let (runs, loops) = join(vec![c, a, b], 1e-9, None);
        assert!(loops.is_empty());
        assert_eq!(runs.len(), 1);
        let p = &runs[0].pts;
        let ends = [p[0], p[p.len() - 1]];
        assert!(ends.contains(&[0.0, 0.0]) && ends.contains(&[2.0, 3.0]), "{p:?}");
        assert_eq!(p.len(), 4);

        let l = chain(&[[0.0, 0.0], [-1.0, 1.0]], 0);
        let r = chain(&[[0.0, 0.0], [1.0, 1.0]], 1);
        assert_eq!(join(vec![l.clone(), r.clone()], 1e-9, Some(0.0)).0.len(), 2);
        assert_eq!(join(vec![l.clone(), r.clone()], 1e-9, None).0.len(), 1);
        let third = chain(&[[0.0, 0.0], [0.0, 2.0]], 2);
        assert_eq!(join(vec![l, r, third], 1e-9, None).0.len(), 3);

        let sq = vec![
            chain(&[[0.0, 0.0], [1.0, 0.0]], 0),
            chain(&[[1.0, 0.0], [0.0, 1.0]], 1),
            chain(&[[0.0, 1.0], [0.0, 0.0]], 2),
        ];
        let (runs, loops) = join(sq, 1e-9, None);
        assert!(runs.is_empty());
        assert_eq!(loops.len(), 1);
    }
}
