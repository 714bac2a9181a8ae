//! Which drawn runs are which station, and where each station is along the hull: by labels,
//! by layers or by the order of the curves, with the x of a list, a map or a spacing.

use std::cmp::Ordering;

use super::geom::polyline_dist;
use super::{drawing_error, Sketch};
use crate::error::{DigitizeKind, HullError, Location};

use super::join::{join, Chain};
use super::map::Found;
use super::options::{CurveOrder, DigitizeOptions, StationIds, StationX};

/// The station number in a name: a number, optionally after `station`, `stn`, `sta`, `st`,
/// `s` or `#` (any case) and a space, `.` or `_`; the number may be negative, decimal, or
/// have a fraction (`9 1/2`, `9½`, `9¼`, `9¾`). `ST10` is 10, `Station 7.5` is 7.5, `9 1/2`
/// is 9.5; `path12` and `WL1` have none.
pub fn label_number(name: &str) -> Option<f64> {
    let lower = name.trim().to_lowercase();
    let mut t = lower.as_str();
    for prefix in ["station", "stn", "sta", "st", "s", "#"] {
        if let Some(r) = t.strip_prefix(prefix) {
            t = r;
            break;
        }
    }
    let t = t.trim_start_matches(['.', '_', ' ']);
    let (t, frac) = match t.char_indices().last() {
        Some((i, '½')) => (&t[..i], 0.5),
        Some((i, '¼')) => (&t[..i], 0.25),
        Some((i, '¾')) => (&t[..i], 0.75),
        _ => (t, 0.0),
    };
    let whole = |w: &str| if w.is_empty() && frac > 0.0 { Some(0.0) } else { w.parse::<f64>().ok() };
    let v = match t.split_once(' ') {
        Some((w, f)) if frac == 0.0 => {
            let (a, b) = f.trim().split_once('/')?;
            let (a, b) = (a.parse::<u32>().ok()?, b.parse::<u32>().ok()?);
            if b == 0 || a >= b {
                return None;
            }
            let w = w.parse::<f64>().ok()?;
            let sign = if w.is_sign_negative() { -1.0 } else { 1.0 };
            w + sign * f64::from(a) / f64::from(b)
        }
        Some(_) => return None,
        None => {
            let w = whole(t)?;
            w + if t.starts_with('-') { -frac } else { frac }
        }
    };
    v.is_finite().then_some(v)
}

/// Compare station names: by station number when both have one, else alphabetically
/// (case-insensitive).
fn name_order(a: &str, b: &str) -> Ordering {
    match (label_number(a), label_number(b)) {
        (Some(x), Some(y)) => x.total_cmp(&y),
        _ => a.to_lowercase().cmp(&b.to_lowercase()),
    }
}

/// The labelled stations of [`StationIds::Labels`].
pub(super) fn by_labels(
    sketch: &Sketch,
    o: &DigitizeOptions,
    chains: Vec<Chain>,
    tol: f64,
    notes: &mut Vec<String>,
) -> Result<Vec<Found>, HullError> {
    let accepted = |t: &str| match &o.x {
        StationX::Map(m) => m.iter().any(|(k, _)| k.trim().eq_ignore_ascii_case(t.trim())),
        _ => label_number(t).is_some(),
    };
    // Names of the curves themselves (SVG titles and ids) first.
    let mut label: Vec<Option<(String, Location)>> = chains
        .iter()
        .map(|c| {
            c.curves().into_iter().find_map(|i| {
                let cv = &sketch.curves[i];
                cv.name.as_ref().filter(|n| accepted(n)).map(|n| (n.clone(), cv.at.clone()))
            })
        })
        .collect();
    let named: Vec<bool> = label.iter().map(Option::is_some).collect();
    let limit = o.label_distance.filter(|d| d.is_finite() && *d >= 0.0).unwrap_or(f64::INFINITY);
    let mut far = 0;
    for l in sketch.labels.iter().filter(|l| accepted(&l.text)) {
        let nearest = chains
            .iter()
            .enumerate()
            .filter(|(k, _)| !named[*k])
            .map(|(k, c)| (k, polyline_dist(l.at, &c.pts)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match nearest {
            Some((k, d)) if d <= limit => match &label[k] {
                Some((t, at)) if !t.trim().eq_ignore_ascii_case(l.text.trim()) => {
                    return Err(drawing_error(
                        l.loc.clone(),
                        format!(
                            "label {:?} and label {t:?} (at {at}) are both nearest to {}",
                            l.text,
                            sketch.curves[chains[k].first_curve()].describe()
                        ),
                        "one label per station curve: move each label next to its curve, or limit --label-distance",
                    ))
                }
                Some(_) => {}
                None => label[k] = Some((l.text.clone(), l.loc.clone())),
            },
            _ => far += 1,
        }
    }
    if far > 0 {
        notes.push(format!("{far} station label(s) farther than {limit} drawing units from every curve ignored"));
    }
    let mut groups: Vec<(String, Vec<Chain>)> = Vec::new();
    let mut unlabelled = Vec::new();
    for (c, l) in chains.into_iter().zip(label) {
        match l {
            Some((t, _)) => match groups.iter_mut().find(|g| g.0.trim().eq_ignore_ascii_case(t.trim())) {
                Some(g) => g.1.push(c),
                None => groups.push((t.trim().to_string(), vec![c])),
            },
            None => unlabelled.push(c.first_curve()),
        }
    }
    if let Some(first) = unlabelled.iter().min() {
        notes.push(format!(
            "{} curve(s) without a station label skipped, first {}",
            unlabelled.len(),
            sketch.curves[*first].describe()
        ));
    }
    let mut found = Vec::new();
    for (label, chains) in groups {
        let (chains, loops) = join(chains, tol, None);
        for l in loops {
            notes.push(format!(
                "station {label:?}: closed loop skipped, first {}",
                sketch.curves[l.first_curve()].describe()
            ));
        }
        if !chains.is_empty() {
            found.push(Found { label, chains });
        }
    }
    Ok(found)
}

/// Sort the chains of [`StationIds::Order`].
pub(super) fn order_chains(sketch: &Sketch, chains: &mut [Chain], order: CurveOrder, x0: f64, tol: f64) {
    match order {
        CurveOrder::Drawn => chains.sort_by_key(Chain::first_curve),
        CurveOrder::Layer => chains.sort_by(|a, b| {
            name_order(&sketch.curves[a.first_curve()].layer, &sketch.curves[b.first_curve()].layer)
                .then(a.first_curve().cmp(&b.first_curve()))
        }),
        CurveOrder::BodyPlan => {
            // Signed reach: -(widest) for the left (aft), +(widest) for the right; aft from
            // the narrowest (closest to 0 from below... i.e. reach -small first), fore widest first.
            let key = |c: &Chain| {
                let left = c.pts.iter().map(|p| x0 - p[0]).fold(0.0, f64::max);
                let right = c.pts.iter().map(|p| p[0] - x0).fold(0.0, f64::max);
                if right > tol {
                    (2, -right)
                } else if left > tol {
                    (1, left)
                } else {
                    (0, 0.0)
                }
            };
            chains.sort_by(|a, b| {
                let (ka, kb) = (key(a), key(b));
                ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1)).then(a.first_curve().cmp(&b.first_curve()))
            });
        }
    }
}

/// The x of each found station (and `found` sorted to the list's order for lists).
pub(super) fn station_xs(
    sketch: &Sketch,
    o: &DigitizeOptions,
    found: &mut [Found],
    notes: &mut Vec<String>,
) -> Result<Vec<f64>, HullError> {
    let by_order = matches!(o.stations, StationIds::Order(_));
    let at = |f: &Found| sketch.curves[f.chains[0].first_curve()].at.clone();
    match &o.x {
        StationX::List(xs) => {
            if !by_order {
                found.sort_by(|a, b| name_order(&a.label, &b.label));
            }
            if xs.len() != found.len() {
                return Err(HullError::Digitize(DigitizeKind::StationCount {
                    drawing: sketch.source.clone(),
                    found: found.iter().map(|f| f.label.clone()).collect(),
                    given: xs.len(),
                }));
            }
            if let Some(x) = xs.iter().find(|x| !x.is_finite()) {
                return Err(HullError::Digitize(DigitizeKind::StationPosition { x: *x }));
            }
            Ok(xs.clone())
        }
        StationX::Map(map) => {
            if by_order {
                return Err(HullError::Digitize(DigitizeKind::NamesByOrder));
            }
            let mut out = Vec::with_capacity(found.len());
            for f in found.iter() {
                match map.iter().find(|(k, _)| k.trim().eq_ignore_ascii_case(f.label.trim())) {
                    Some((_, x)) if x.is_finite() => out.push(*x),
                    Some((k, x)) => {
                        return Err(HullError::Digitize(DigitizeKind::NamedStation { name: k.clone(), x: *x }))
                    }
                    None => {
                        let names: Vec<&str> = map.iter().map(|(k, _)| k.as_str()).collect();
                        return Err(drawing_error(
                            at(f),
                            format!(
                                "unknown station {:?}: it is not among the stations given ({})",
                                f.label,
                                names.join(", ")
                            ),
                            "a position for every station drawn: add it to the station list, or narrow the layers",
                        ));
                    }
                }
            }
            for (k, _) in map {
                if !found.iter().any(|f| f.label.trim().eq_ignore_ascii_case(k.trim())) {
                    notes.push(format!("station {k:?} was given but is not in the drawing"));
                }
            }
            Ok(out)
        }
        StationX::Spacing { origin, spacing } => {
            if !(origin.is_finite() && spacing.is_finite() && *spacing != 0.0) {
                return Err(HullError::Digitize(DigitizeKind::Spacing { origin: *origin, spacing: *spacing }));
            }
            found
                .iter()
                .enumerate()
                .map(|(k, f)| {
                    let n = if by_order { Some(k as f64) } else { label_number(&f.label) };
                    n.map(|n| origin + n * spacing).ok_or_else(|| {
                        drawing_error(
                            at(f),
                            format!("station {:?} has no station number", f.label),
                            "names such as 7, ST7, Station 7.5 or 9 1/2 with a station spacing, or the positions listed",
                        )
                    })
                })
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn station_numbers_in_names() {
        for (name, n) in [
            ("7", Some(7.0)),
            ("ST10", Some(10.0)),
            ("st 3", Some(3.0)),
            ("Station 7.5", Some(7.5)),
            ("STN_2", Some(2.0)),
            ("St. 4", Some(4.0)),
            ("9 1/2", Some(9.5)),
            ("9½", Some(9.5)),
            ("½", Some(0.5)),
            ("-1", Some(-1.0)),
            ("ST-1", Some(-1.0)),
            ("#12", Some(12.0)),
            ("path12", None),
            ("WL1", None),
            ("CL", None),
            ("9 1/0", None),
            ("", None),
        ] {
            assert_eq!(label_number(name), n, "{name:?}");
        }
        assert_eq!(name_order("ST2", "ST10"), Ordering::Less);
        assert_eq!(name_order("aft", "Bow"), Ordering::Less);
    }
}
