//! The surface integrals behind the hydrostatics: Gauss-Legendre quadrature over the knot-span
//! cells of the parameter domain, clipped at a level set (`z = T` for the wet surface, `x = x_m`
//! for the midship section) located by root finding, with the line integrals along the cut.
//!
//! A cell cut by the level set `f(u, v) = coord(S(u, v)) - c = 0` is integrated as an iterated
//! integral: `f` is checked to be monotone along one parameter (the *inner* one) on the cell,
//! the roots of `f` on the two inner ends of the cell split the *outer* parameter range into
//! intervals on which the cut is one smooth graph `inner = r(outer)`, and on each interval the
//! outer Gauss nodes get their root `r` by Brent's method and an inner Gauss rule over the wet
//! side. The outer integrand is then smooth (analytic inside a span), so the rule converges as
//! fast as on an uncut cell. A cell monotone in neither direction is split in four, down to
//! [`MAX_DEPTH`] levels.
//!
//! The surface along the inner parameter at an outer node, with its derivatives, the roots of
//! the level set and the cut's tangent, is the kernel's [`nurbs::IsoCurve`].

use nurbs::basis::{ders_basis_funs, BasisRow};
use nurbs::{
    brent_max, brent_root, Axis, Direction, FirstDerivatives, GaussLegendre, IsoCurve, NurbsSurface, Vec3, MAX_DEGREE,
};

/// How far a level edge of a fitted surface may lie above the waterline and still be it, in
/// ulps of the largest |z| of the control net: a cell whose control points lie no higher is
/// wet whole, and a domain edge within it of the level is the waterline (the top of the
/// offsets, where the design draft often is). A least-squares fit leaves a level edge level
/// only to its own round-off: the Wigley table's approximation (9x16) has its top edge's
/// control points within 10 ulps of z = 6.25 with one order of summation in the band Cholesky
/// factor and within 17 with another, and the waterline's lift of 16 ulps ([`Integrator::eps`])
/// alone lost the edge there (Lwl 78.3 for 100). 1024 ulps (1.4e-12 there) leaves a 60-fold
/// margin; only the cells within it of the level are affected (by at most their waterplane
/// area times it), not the cut cells of every other draft.
pub(crate) const EDGE_ULPS: f64 = 1024.0;

/// Subdivision levels of a cell where the level set is monotone in neither parameter.
const MAX_DEPTH: usize = 6;
/// Samples per cell edge when looking for the level set's crossings.
const EDGE_SAMPLES: usize = 8;
/// Samples per direction of the derivative sign test of a cell.
const SIGN_SAMPLES: usize = 4;
/// Half-thickness of the centre-plane slab, relative to the control net's diagonal: a knot
/// span whose control points all lie within `|y| <= WEB_REL x size` is in the slab, and a web
/// unless joined to a keel line ([`web_spans`]). Measured (largest `|y|` of a span's control
/// points over the diagonal, surfaces fitted by approx and interp): the DTC's bow web, sliced
/// at 41 stations, has seven spans at 1.1e-4 .. 2.0e-3 (interpolation rings about the centre
/// plane) and one at 1.5e-3 (approximation; the next at 2.8e-3). Of the other hulls at hand
/// the thinnest span is R/V Gunnerus's skeg at 3.0e-3 (interp; 3.3e-3 approx); Series 60 Cb
/// 0.60 and 0.80, the Wigley offsets and the 116 m cargo ship have none below 1e-2, the exact
/// Wigley patch none below 1.1e-2. The fine ends that come below (the forefoot of the OpenFOAM
/// Wigley mesh sliced at 41 stations, 5.6e-4; DTMB 5415's stem above its sonar dome, 7.7e-4)
/// are joined to the keel line. 2e-3 keeps Gunnerus's skeg out by a third.
pub(crate) const WEB_REL: f64 = 2e-3;

/// The coordinates the level sets are taken of: `x` (the midship
/// section `x = x_m`) and `z` (the waterline `z = T`).
const X: Axis = Axis::X;
const Z: Axis = Axis::Z;

/// A rectangle of the parameter domain.
#[derive(Clone, Copy, Debug)]
struct Rect {
    u: (f64, f64),
    v: (f64, f64),
}

impl Rect {
    fn range(&self, d: Direction) -> (f64, f64) {
        match d {
            Direction::U => self.u,
            Direction::V => self.v,
        }
    }

    fn quarters(&self) -> [Rect; 4] {
        let um = 0.5 * (self.u.0 + self.u.1);
        let vm = 0.5 * (self.v.0 + self.v.1);
        [
            Rect { u: (self.u.0, um), v: (self.v.0, vm) },
            Rect { u: (um, self.u.1), v: (self.v.0, vm) },
            Rect { u: (self.u.0, um), v: (vm, self.v.1) },
            Rect { u: (um, self.u.1), v: (vm, self.v.1) },
        ]
    }
}

/// `(u, v)` from an inner and an outer parameter value.
fn uv(inner: Direction, i: f64, o: f64) -> (f64, f64) {
    match inner {
        Direction::U => (i, o),
        Direction::V => (o, i),
    }
}

/// The orientation factor of a cut traversed with increasing outer parameter, for the
/// counter-clockwise boundary (u to the right, v up) of the wet region: the wet region
/// `{u < r(v)}` lies left of a cut traversed upward (+1), `{v < r(u)}` left of a cut
/// traversed toward -u (-1).
fn orientation(inner: Direction, wet_low: bool) -> f64 {
    match (inner, wet_low) {
        (Direction::U, true) | (Direction::V, false) => 1.0,
        (Direction::U, false) | (Direction::V, true) => -1.0,
    }
}

/// An outer interval `(s0, s1)` of a cell between two breaks of a level set, with whether the
/// level set's low side holds at the cell's two inner ends ([`Integrator::strips`]).
#[derive(Clone, Copy, Debug)]
struct Strip {
    s0: f64,
    s1: f64,
    low: (bool, bool),
}

/// A knot-span cell (or a part of one) with the bounding box of the span's control points,
/// which holds the surface over the span (convex hull property, positive weights).
#[derive(Clone, Copy, Debug)]
struct Cell {
    rect: Rect,
    lo: Vec3,
    hi: Vec3,
    /// The span lies in the centre plane: its control points, hence (convex hull) the whole
    /// span, within `|y| <= WEB_REL x size`. Such a piece of surface is a zero-thickness web
    /// between two parts of the hull (a section sliced from a mesh as two pieces joined along
    /// the centre plane: bulb and stem, skeg and hull): inside the mirrored hull, never wetted.
    /// Its area is summed apart ([`Sums::web`]) and its waterline pieces are left out of the
    /// waterline's extent. Whole spans are classified, so the integration stays the same tensor
    /// and clipped rules (no cell is cut by the web's boundary, which runs along knot lines).
    web: bool,
}

/// A piece of one knot span of a domain edge, with its control points' z range.
#[derive(Clone, Copy, Debug)]
struct EdgeSeg {
    /// The parameter held fixed, and its value.
    fixed: Direction,
    value: f64,
    /// The range of the other parameter.
    range: (f64, f64),
    /// +1 or -1: the direction of the counter-clockwise boundary of the domain.
    orient: f64,
    zlo: f64,
    zhi: f64,
    /// The edge's control points lie in the centre plane (as [`Cell::web`]).
    web: bool,
}

/// Integrals of one draft over the starboard half, the orientation of the surface not yet
/// applied (the caller multiplies by the sign of `vol`). With `n = S_u x S_v` and
/// `x0` the reference abscissa:
///
/// * `vol = int y n_y`, `mx = int (x - x0) y n_y`, `mz = int z y n_y`, `area = int |n|`,
///   `pxy = int -n_z` (the wet surface's signed projection on the waterplane), all over the
///   wet part of the domain, `du dv`; `area` over the spans off the centre plane, `web` over
///   the spans in it ([`Cell::web`]);
/// * `wa = int y dx`, `wx = int (x - x0) y dx`, `wt = int y^3 / 3 dx`,
///   `wxx = int (x - x0)^2 y dx` along the waterline cut, counter-clockwise around the wet part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Sums {
    pub vol: f64,
    pub mx: f64,
    pub mz: f64,
    pub area: f64,
    pub web: f64,
    pub pxy: f64,
    pub wa: f64,
    pub wx: f64,
    pub wt: f64,
    pub wxx: f64,
}

/// A piece of the waterline, kept to find its extremes.
#[derive(Clone, Debug)]
enum Piece {
    /// The cut across a cell: `inner = r(outer)`, sampled at increasing outer values.
    Cut { rect: Rect, inner: Direction, samples: Vec<(f64, Vec3)>, web: bool },
    /// A domain edge lying on the waterline.
    Edge { fixed: Direction, value: f64, samples: Vec<(f64, Vec3)>, web: bool },
}

impl Piece {
    fn samples(&self) -> &[(f64, Vec3)] {
        match self {
            Piece::Cut { samples, .. } | Piece::Edge { samples, .. } => samples,
        }
    }

    /// Whether the piece runs across a web (a span in the centre plane).
    fn web(&self) -> bool {
        matches!(self, Piece::Cut { web: true, .. } | Piece::Edge { web: true, .. })
    }
}

/// The wet part of the surface at one level.
#[derive(Clone, Debug, Default)]
pub(crate) struct Wet {
    pub sums: Sums,
    pieces: Vec<Piece>,
    /// Cells still not monotone after [`MAX_DEPTH`] subdivisions (integrated anyway, less
    /// accurately).
    pub unresolved: usize,
}

/// A surface prepared for integration: its cells, edges and extents.
#[derive(Clone, Debug)]
pub(crate) struct Integrator<'a> {
    s: &'a NurbsSurface,
    gl: GaussLegendre,
    cells: Vec<Cell>,
    edges: Vec<EdgeSeg>,
    /// Highest and lowest z found on a sample grid of the surface.
    pub top: f64,
    pub bottom: f64,
    /// Reference abscissa of the longitudinal moments (middle of the net's x range).
    pub x0: f64,
    /// Round-off of a z coordinate: 16 ulps of the largest |z| of the control net.
    pub eps: f64,
    /// How far above the waterline a level edge may lie and still be it ([`EDGE_ULPS`]).
    edge_slack: f64,
    /// Diagonal of the control net's bounding box.
    pub size: f64,
    /// Whether any knot span is a web ([`web_spans`]).
    pub has_web: bool,
}

impl<'a> Integrator<'a> {
    /// Cells of `split x split` per knot span, `order` Gauss points per direction and cell.
    pub(crate) fn new(s: &'a NurbsSurface, order: usize, split: usize) -> Self {
        let split = split.max(1);
        let (p, q) = (s.degree_u(), s.degree_v());
        let (nu, nv) = (s.n_u(), s.n_v());
        let ku = s.knots_u().as_slice();
        let kv = s.knots_v().as_slice();
        let spans_u: Vec<usize> = (p..nu).filter(|&i| ku[i] < ku[i + 1]).collect();
        let spans_v: Vec<usize> = (q..nv).filter(|&j| kv[j] < kv[j + 1]).collect();
        let bounds = |is: std::ops::RangeInclusive<usize>, js: std::ops::RangeInclusive<usize>| {
            let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
            let mut hi = -lo;
            for i in is {
                for j in js.clone() {
                    let c = s.control_point(i, j);
                    lo = Vec3::new(lo.x.min(c.x), lo.y.min(c.y), lo.z.min(c.z));
                    hi = Vec3::new(hi.x.max(c.x), hi.y.max(c.y), hi.z.max(c.z));
                }
            }
            (lo, hi)
        };
        let pieces = |a: f64, b: f64| -> Vec<(f64, f64)> {
            (0..split)
                .map(|k| {
                    let lo = a + (b - a) * k as f64 / split as f64;
                    let hi = if k + 1 == split { b } else { a + (b - a) * (k + 1) as f64 / split as f64 };
                    (lo, hi)
                })
                .collect()
        };
        let (net_lo, net_hi) = s.control_bounds();
        let webs = web_spans(s, &spans_u, &spans_v, WEB_REL * (net_hi - net_lo).norm());
        let nsv = spans_v.len();
        let mut cells = Vec::new();
        for (a, &i) in spans_u.iter().enumerate() {
            for (b, &j) in spans_v.iter().enumerate() {
                let (lo, hi) = bounds(i - p..=i, j - q..=j);
                let web = webs[a * nsv + b];
                for &u in &pieces(ku[i], ku[i + 1]) {
                    for &v in &pieces(kv[j], kv[j + 1]) {
                        cells.push(Cell { rect: Rect { u, v }, lo, hi, web });
                    }
                }
            }
        }
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        let mut edges = Vec::new();
        for (a, &i) in spans_u.iter().enumerate() {
            for (jj, value, orient, b) in [(0, v0, 1.0, 0), (nv - 1, v1, -1.0, nsv.saturating_sub(1))] {
                let (lo, hi) = bounds(i - p..=i, jj..=jj);
                let web = webs[a * nsv + b];
                for &range in &pieces(ku[i], ku[i + 1]) {
                    edges.push(EdgeSeg { fixed: Direction::V, value, range, orient, zlo: lo.z, zhi: hi.z, web });
                }
            }
        }
        for (b, &j) in spans_v.iter().enumerate() {
            for (ii, value, orient, a) in [(0, u0, -1.0, 0), (nu - 1, u1, 1.0, spans_u.len().saturating_sub(1))] {
                let (lo, hi) = bounds(ii..=ii, j - q..=j);
                let web = webs[a * nsv + b];
                for &range in &pieces(kv[j], kv[j + 1]) {
                    edges.push(EdgeSeg { fixed: Direction::U, value, range, orient, zlo: lo.z, zhi: hi.z, web });
                }
            }
        }
        let (lo, hi) = s.control_bounds();
        let ulp = f64::EPSILON * lo.z.abs().max(hi.z.abs()).max(f64::MIN_POSITIVE);
        let (eps, edge_slack) = (16.0 * ulp, EDGE_ULPS * ulp);
        let size = (hi - lo).norm();
        // Sampled extent in z: 8 intervals per knot span and direction, span ends included.
        let samples = |k: &[f64], spans: &[usize]| -> Vec<f64> {
            let mut out = Vec::new();
            for &i in spans {
                for m in 0..8 {
                    out.push(k[i] + (k[i + 1] - k[i]) * m as f64 / 8.0);
                }
            }
            if let Some(&last) = spans.last() {
                out.push(k[last + 1]);
            }
            out
        };
        let (mut top, mut bottom) = (f64::NEG_INFINITY, f64::INFINITY);
        let sv = samples(kv, &spans_v);
        for &u in &samples(ku, &spans_u) {
            for &v in &sv {
                let z = s.point(u, v).z;
                top = top.max(z);
                bottom = bottom.min(z);
            }
        }
        let has_web = webs.contains(&true);
        Integrator {
            s,
            gl: GaussLegendre::new(order),
            cells,
            edges,
            top,
            bottom,
            x0: 0.5 * (lo.x + hi.x),
            eps,
            edge_slack,
            size,
            has_web,
        }
    }

    /// The point and first partial derivatives at `(u, v)`: The NURBS Book A3.6 on the
    /// homogeneous net to first order, then A4.4, `S_u = (A_u - w_u S) / w` (as
    /// [`NurbsSurface::derivatives`], without the second derivatives this module never uses).
    fn d1(&self, u: f64, v: f64) -> FirstDerivatives {
        let (ku, kv) = (self.s.knots_u(), self.s.knots_v());
        let (u, v) = (ku.clamp(u), kv.clamp(v));
        self.iso(Direction::V, u, (ku.find_span(u), kv.find_span(v))).derivatives(v)
    }

    /// The knot spans `(i, j)` holding the rectangle `r` (which lies in one span).
    fn spans(&self, r: &Rect) -> (usize, usize) {
        (self.s.knots_u().find_span(0.5 * (r.u.0 + r.u.1)), self.s.knots_v().find_span(0.5 * (r.v.0 + r.v.1)))
    }

    /// The surface along `inner` at the outer parameter `s`, over the knot spans `(su, sv)`.
    fn iso(&self, inner: Direction, s: f64, spans: (usize, usize)) -> IsoCurve<'a> {
        IsoCurve::new(self.s, inner, s, spans)
    }

    /// `S(u, v)[coord] - c`.
    fn f(&self, coord: Axis, c: f64, (u, v): (f64, f64)) -> f64 {
        self.s.point(u, v)[coord] - c
    }

    /// The wet part of the surface below the level `level` (`z <= level`): the surface
    /// integrals, the waterline integrals and the waterline's pieces. Edges of the domain
    /// whose control points all lie within `band` below `level` are the waterline (a hull
    /// whose top edge is the waterline, like the Wigley hull at its draft), both bounds
    /// widened by the round-off of a fitted level edge ([`EDGE_ULPS`]).
    pub(crate) fn wet(&self, level: f64, band: f64) -> Wet {
        let mut wet = Wet::default();
        for cell in &self.cells {
            if cell.hi.z <= level + self.edge_slack {
                self.full(cell.rect, cell.web, &mut wet.sums);
            } else if cell.lo.z <= level {
                self.cut(cell.rect, cell.web, level, 0, &mut wet);
            }
        }
        for e in &self.edges {
            if e.zlo >= level - band - self.edge_slack && e.zhi <= level + self.edge_slack {
                self.edge_waterline(e, &mut wet);
            }
        }
        wet
    }

    /// Tensor Gauss rule over a wet rectangle (the v basis computed once per node column), in
    /// a web span if `web`.
    fn full(&self, r: Rect, web: bool, sums: &mut Sums) {
        let spans = self.spans(&r);
        let kv = self.s.knots_v().as_slice();
        let q = self.s.degree_v();
        let bv: Vec<(f64, [BasisRow; 2])> = self
            .gl
            .on(r.v.0, r.v.1)
            .map(|(v, w)| {
                let mut b: [BasisRow; 2] = [[0.0; MAX_DEGREE + 1]; 2];
                ders_basis_funs(kv, spans.1, v, q, 1, &mut b);
                (w, b)
            })
            .collect();
        for (u, wu) in self.gl.on(r.u.0, r.u.1) {
            let iso = self.iso(Direction::V, u, spans);
            for (wv, b) in &bv {
                self.area_node(iso.derivatives_with_basis(b), wu * wv, web, sums);
            }
        }
    }

    fn area_node(&self, d: FirstDerivatives, w: f64, web: bool, sums: &mut Sums) {
        let n = d.su.cross(d.sv);
        let p = d.point;
        let yn = w * p.y * n.y;
        sums.vol += yn;
        sums.mx += (p.x - self.x0) * yn;
        sums.mz += p.z * yn;
        if web {
            sums.web += w * n.norm();
        } else {
            sums.area += w * n.norm();
        }
        sums.pxy -= w * n.z;
    }

    fn line_node(&self, p: Vec3, dx: f64, w: f64, sums: &mut Sums) {
        let (xr, yd) = (p.x - self.x0, w * p.y * dx);
        sums.wa += yd;
        sums.wx += xr * yd;
        sums.wt += w * p.y * p.y * p.y / 3.0 * dx;
        sums.wxx += xr * xr * yd;
    }

    /// Which parameter the level set of `coord` is monotone along on `r` (the one with the
    /// larger smallest `|df| * width` on a grid of interior samples), with the outer breaks:
    /// the outer range split at the level set's crossings of the two inner ends. `None` if `f`
    /// is monotone along neither parameter (unless `force`).
    fn plan(&self, r: Rect, coord: Axis, c: f64, force: bool) -> Option<(Direction, Vec<f64>)> {
        let mut pos = [0usize; 2];
        let mut neg = [0usize; 2];
        let mut min = [f64::INFINITY; 2];
        let mut sum = [0.0f64; 2];
        let (wu, wv) = (r.u.1 - r.u.0, r.v.1 - r.v.0);
        let spans = self.spans(&r);
        for a in 0..SIGN_SAMPLES {
            let u = r.u.0 + wu * (a as f64 + 0.5) / SIGN_SAMPLES as f64;
            let iso = self.iso(Direction::V, u, spans);
            for b in 0..SIGN_SAMPLES {
                let v = r.v.0 + wv * (b as f64 + 0.5) / SIGN_SAMPLES as f64;
                let d = iso.derivatives(v);
                for (k, g) in [d.su[coord] * wu, d.sv[coord] * wv].into_iter().enumerate() {
                    if g > 0.0 {
                        pos[k] += 1;
                    } else if g < 0.0 {
                        neg[k] += 1;
                    }
                    min[k] = min[k].min(g.abs());
                    sum[k] += g.abs();
                }
            }
        }
        let n = SIGN_SAMPLES * SIGN_SAMPLES;
        let monotone = |k: usize| pos[k] == n || neg[k] == n;
        let inner = match (monotone(0), monotone(1)) {
            (true, true) => {
                if min[0] >= min[1] {
                    Direction::U
                } else {
                    Direction::V
                }
            }
            (true, false) => Direction::U,
            (false, true) => Direction::V,
            (false, false) if force => {
                if sum[0] >= sum[1] {
                    Direction::U
                } else {
                    Direction::V
                }
            }
            (false, false) => return None,
        };
        let (ia, ib) = r.range(inner);
        let (sa, sb) = r.range(inner.other());
        let mut breaks = vec![sa, sb];
        for i in [ia, ib] {
            let edge = self.iso(inner.other(), i, spans);
            breaks.extend(segment_roots(|s| edge.point(s)[coord] - c, sa, sb));
        }
        breaks.sort_by(f64::total_cmp);
        let tiny = 1e-14 * (sb - sa);
        breaks.dedup_by(|b, a| *b - *a <= tiny);
        if let Some(last) = breaks.last_mut() {
            *last = sb;
        }
        Some((inner, breaks))
    }

    /// [`Integrator::plan`] as strips: the outer intervals `(s0, s1)` between the breaks, each
    /// with whether the level set's low side `S[coord] <= c` holds at the two inner ends at its
    /// middle, `(low at the first end, low at the second)`. `None` as `plan`.
    fn strips(&self, r: Rect, coord: Axis, c: f64, force: bool) -> Option<(Direction, Vec<Strip>)> {
        let (inner, breaks) = self.plan(r, coord, c, force)?;
        let (ia, ib) = r.range(inner);
        let strips = breaks
            .windows(2)
            .filter(|w| w[1] > w[0])
            .map(|w| {
                let mid = 0.5 * (w[0] + w[1]);
                let low = |i: f64| self.f(coord, c, uv(inner, i, mid)) <= 0.0;
                Strip { s0: w[0], s1: w[1], low: (low(ia), low(ib)) }
            })
            .collect();
        Some((inner, strips))
    }

    /// A cell cut by the waterline `z = level` (in a web span if `web`).
    fn cut(&self, r: Rect, web: bool, level: f64, depth: usize, wet: &mut Wet) {
        let Some((inner, strips)) = self.strips(r, Z, level, depth >= MAX_DEPTH) else {
            for q in r.quarters() {
                self.cut(q, web, level, depth + 1, wet);
            }
            return;
        };
        if depth >= MAX_DEPTH {
            wet.unresolved += 1;
        }
        let spans = self.spans(&r);
        let (ia, ib) = r.range(inner);
        for Strip { s0, s1, low: (wet_a, wet_b) } in strips {
            if wet_a && wet_b {
                let sub = match inner {
                    Direction::U => Rect { u: (ia, ib), v: (s0, s1) },
                    Direction::V => Rect { u: (s0, s1), v: (ia, ib) },
                };
                self.full(sub, web, &mut wet.sums);
                continue;
            }
            if !wet_a && !wet_b {
                continue;
            }
            let omega = orientation(inner, wet_a);
            let mut samples = Vec::with_capacity(self.gl.len() + 2);
            let iso0 = self.iso(inner, s0, spans);
            if let Some(rr) = iso0.root(Z, level, ia, ib) {
                samples.push((s0, iso0.point(rr)));
            }
            for (s, ws) in self.gl.on(s0, s1) {
                let iso = self.iso(inner, s, spans);
                let rr = iso.root_or_end(Z, level, ia, ib);
                let (lo, hi) = if wet_a { (ia, rr) } else { (rr, ib) };
                for (i, wi) in self.gl.on(lo, hi) {
                    self.area_node(iso.derivatives(i), ws * wi, web, &mut wet.sums);
                }
                let (p, t) = iso.cut_point(Z, rr);
                self.line_node(p, t.x, ws * omega, &mut wet.sums);
                samples.push((s, p));
            }
            let iso1 = self.iso(inner, s1, spans);
            if let Some(rr) = iso1.root(Z, level, ia, ib) {
                samples.push((s1, iso1.point(rr)));
            }
            wet.pieces.push(Piece::Cut { rect: r, inner, samples, web });
        }
    }

    /// A domain edge lying on the waterline: its line integrals, counter-clockwise.
    fn edge_waterline(&self, e: &EdgeSeg, wet: &mut Wet) {
        let at = |s: f64| match e.fixed {
            Direction::U => (e.value, s),
            Direction::V => (s, e.value),
        };
        let point = |s: f64| {
            let (u, v) = at(s);
            self.s.point(u, v)
        };
        let mut samples = vec![(e.range.0, point(e.range.0))];
        for (s, ws) in self.gl.on(e.range.0, e.range.1) {
            let (u, v) = at(s);
            let d = self.d1(u, v);
            let t = match e.fixed {
                Direction::U => d.sv,
                Direction::V => d.su,
            };
            self.line_node(d.point, t.x, ws * e.orient, &mut wet.sums);
            samples.push((s, d.point));
        }
        samples.push((e.range.1, point(e.range.1)));
        wet.pieces.push(Piece::Edge { fixed: e.fixed, value: e.value, samples, web: e.web });
    }

    /// A point of a waterline piece at its parameter `s`.
    fn piece_point(&self, piece: &Piece, level: f64, s: f64) -> Option<Vec3> {
        match piece {
            Piece::Cut { rect, inner, .. } => {
                let (ia, ib) = rect.range(*inner);
                let iso = self.iso(*inner, s, self.spans(rect));
                iso.root(Z, level, ia, ib).map(|r| iso.point(r))
            }
            Piece::Edge { fixed, value, .. } => Some(match fixed {
                Direction::U => self.s.point(*value, s),
                Direction::V => self.s.point(s, *value),
            }),
        }
    }

    /// The largest `g(p)` over the waterline off the centre plane (the pieces across web spans
    /// left out): the best samples of the best four pieces, refined by Brent's maximiser
    /// between their neighbouring samples. `None` without such a waterline.
    pub(crate) fn waterline_max(&self, wet: &Wet, level: f64, g: impl Fn(Vec3) -> f64) -> Option<(f64, Vec3)> {
        let mut best: Vec<(f64, usize, usize)> = wet
            .pieces
            .iter()
            .enumerate()
            .filter(|(_, piece)| !piece.web())
            .filter_map(|(k, piece)| {
                piece.samples().iter().enumerate().map(|(m, &(_, p))| (g(p), k, m)).max_by(|a, b| a.0.total_cmp(&b.0))
            })
            .collect();
        best.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let mut out: Option<(f64, Vec3)> = None;
        for &(_, k, m) in best.iter().take(4) {
            let piece = &wet.pieces[k];
            let samples = piece.samples();
            let lo = samples[m.saturating_sub(1)].0;
            let hi = samples[(m + 1).min(samples.len() - 1)].0;
            let value = |s: f64| self.piece_point(piece, level, s).map_or(f64::NEG_INFINITY, &g);
            let (s, _) = brent_max(value, lo, hi, 1e-12 * (hi - lo));
            let candidates = [Some(samples[m].1), self.piece_point(piece, level, s)];
            for p in candidates.into_iter().flatten() {
                let gp = g(p);
                match out {
                    Some((v, _)) if v >= gp => {}
                    _ => out = Some((gp, p)),
                }
            }
        }
        out
    }

    /// Half the area of the section `x = xm` below `z = level`: `|int y dz|` along the level set
    /// `x = xm` of the surface, clipped at the waterline (the centre plane, the waterline and a
    /// flat bottom at constant z add nothing to `int y dz` around the section).
    pub(crate) fn half_section_area(&self, xm: f64, level: f64) -> f64 {
        let mut sum = 0.0;
        for cell in &self.cells {
            if cell.lo.x <= xm && xm <= cell.hi.x && cell.lo.z <= level {
                self.section_cell(cell.rect, xm, level, 0, &mut sum);
            }
        }
        sum.abs()
    }

    fn section_cell(&self, r: Rect, xm: f64, level: f64, depth: usize, sum: &mut f64) {
        let Some((inner, strips)) = self.strips(r, X, xm, depth >= MAX_DEPTH) else {
            for q in r.quarters() {
                self.section_cell(q, xm, level, depth + 1, sum);
            }
            return;
        };
        let spans = self.spans(&r);
        let (ia, ib) = r.range(inner);
        for Strip { s0, s1, low: (aft_a, aft_b) } in strips {
            if aft_a == aft_b {
                continue;
            }
            let omega = orientation(inner, aft_a);
            let z = |s: f64| {
                let iso = self.iso(inner, s, spans);
                iso.point(iso.root_or_end(X, xm, ia, ib)).z
            };
            // The section curve clipped at the waterline: the parts where z <= level.
            let mut cuts = vec![s0, s1];
            cuts.extend(segment_roots(|s| z(s) - level, s0, s1));
            cuts.sort_by(f64::total_cmp);
            for c in cuts.windows(2) {
                let (a, b) = (c[0], c[1]);
                if b <= a || z(0.5 * (a + b)) > level {
                    continue;
                }
                for (s, ws) in self.gl.on(a, b) {
                    let iso = self.iso(inner, s, spans);
                    let (p, t) = iso.cut_point(X, iso.root_or_end(X, xm, ia, ib));
                    *sum += ws * omega * p.y * t.z;
                }
            }
        }
    }
}

/// Which knot spans are webs, row-major over `spans_u x spans_v` (the spans of nonzero length,
/// by the index of their last knot): a span is *in the slab* when its control points all lie
/// within `|y| <= tol` (so, by the convex hull property, does the span), and a web when it is
/// in the slab but not joined, through spans in the slab sharing a side, to a **keel line**:
/// a domain edge whose control points all lie in the slab and that runs along the ship (its
/// control points' x extent larger than their z extent). That is where the hull closes onto
/// the centre plane (every section starts from it); the spans joined to it that are thinner
/// than `tol` are the hull's fine ends (the forefoot of a densely sliced Wigley hull: spans
/// 0.6 mm thick over 1 cm), wetted on both sides. A web is cut off from the keel line by hull
/// of real breadth (the DTC's bulb below its bow web). An end station in the slab (the DTC's
/// last one, through the bulb's tip and the web) runs up and down, not along: no keel line.
fn web_spans(s: &NurbsSurface, spans_u: &[usize], spans_v: &[usize], tol: f64) -> Vec<bool> {
    let (p, q) = (s.degree_u(), s.degree_v());
    let (nu, nv) = (s.n_u(), s.n_v());
    let (nsu, nsv) = (spans_u.len(), spans_v.len());
    let flat = |c: Vec3| c.y.abs() <= tol;
    let slab: Vec<bool> = spans_u
        .iter()
        .flat_map(|&i| {
            spans_v.iter().map(move |&j| (i - p..=i).all(|a| (j - q..=j).all(|b| flat(s.control_point(a, b)))))
        })
        .collect();
    if !slab.contains(&true) {
        return slab;
    }
    // Seeds: the slab spans along an edge lying in the slab; then a flood fill.
    let mut reached = vec![false; slab.len()];
    let mut stack = Vec::new();
    // An edge in the slab running along the ship (x extent over z extent).
    let keel = |pts: &mut dyn Iterator<Item = Vec3>| {
        let (mut lo, mut hi) =
            (Vec3::new(f64::INFINITY, 0.0, f64::INFINITY), Vec3::new(f64::NEG_INFINITY, 0.0, f64::NEG_INFINITY));
        for c in pts {
            if !flat(c) {
                return false;
            }
            lo = Vec3::new(lo.x.min(c.x), 0.0, lo.z.min(c.z));
            hi = Vec3::new(hi.x.max(c.x), 0.0, hi.z.max(c.z));
        }
        hi.x - lo.x > hi.z - lo.z
    };
    let edge_u = |i: usize| keel(&mut (0..nv).map(|j| s.control_point(i, j)));
    let edge_v = |j: usize| keel(&mut (0..nu).map(|i| s.control_point(i, j)));
    for (on, a) in [(edge_u(0), 0), (edge_u(nu - 1), nsu - 1)] {
        if on {
            stack.extend((0..nsv).map(|b| (a, b)));
        }
    }
    for (on, b) in [(edge_v(0), 0), (edge_v(nv - 1), nsv - 1)] {
        if on {
            stack.extend((0..nsu).map(|a| (a, b)));
        }
    }
    while let Some((a, b)) = stack.pop() {
        let k = a * nsv + b;
        if !slab[k] || reached[k] {
            continue;
        }
        reached[k] = true;
        if a > 0 {
            stack.push((a - 1, b));
        }
        if a + 1 < nsu {
            stack.push((a + 1, b));
        }
        if b > 0 {
            stack.push((a, b - 1));
        }
        if b + 1 < nsv {
            stack.push((a, b + 1));
        }
    }
    slab.iter().zip(&reached).map(|(&in_slab, &r)| in_slab && !r).collect()
}

/// The roots of `g` on `[a, b]`: sign changes ("wet" meaning `g <= 0`) between
/// [`EDGE_SAMPLES`] equal intervals, each refined by Brent's method.
fn segment_roots(g: impl Fn(f64) -> f64, a: f64, b: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut prev = (a, g(a));
    for k in 1..=EDGE_SAMPLES {
        let x = if k == EDGE_SAMPLES { b } else { a + (b - a) * k as f64 / EDGE_SAMPLES as f64 };
        let gx = g(x);
        if (prev.1 <= 0.0) != (gx <= 0.0) {
            out.push(brent_root(&g, prev.0, x, prev.1, gx, 0.0));
        }
        prev = (x, gx);
    }
    out
}
