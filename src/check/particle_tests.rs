//! Tests of [`check_particles`]: hand-built lattices of touching particles
//! and a randomized comparison with brute-force distances.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::Vector2;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::particles::pair_lower;
use super::*;
use crate::geometry::{Outline, Point};

/// The particle `outline` turned by `angle` at (x, y): its disk (centre,
/// area-equivalent radius) and grain.
fn particle(outline: &Outline, angle: f64, x: f64, y: f64) -> (Disk, Grain) {
    (
        Disk::new(x, y, outline.equivalent_radius()),
        Grain::new(outline.clone(), angle),
    )
}

/// Centrally symmetric outlines with their half extents along their own
/// axes (a, b): two copies at the same angle touch at 2a along x, 2b along y.
fn lattice_shapes() -> Vec<(Outline, f64, f64)> {
    let square =
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(x, y)| Point::new(x, y));
    vec![
        (Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap(), 2.0, 1.0),
        (Outline::superellipse(1.5, 1.0, 4.0, 4.0).unwrap(), 1.5, 1.0),
        (Outline::superellipse(3.0, 1.0, 7.0, 1.5).unwrap(), 3.0, 1.0),
        (Outline::superellipse(2.5, 1.0, 1.0, 1.0).unwrap(), 2.5, 1.0),
        (Outline::polygon(0, &square, 0.25).unwrap(), 1.25, 1.25),
    ]
}

/// An `nx` × `ny` lattice of `outline` at angle 0, each touching its
/// neighbours, filling [0, 2a·nx] × [0, 2b·ny]; cells for which `keep` is
/// false are left empty.
fn lattice(
    outline: &Outline,
    (a, b): (f64, f64),
    (nx, ny): (usize, usize),
    keep: impl Fn(usize, usize) -> bool,
) -> (Vec<Disk>, Vec<Grain>) {
    let mut disks = Vec::new();
    let mut grains = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            if keep(i, j) {
                let (d, g) = particle(outline, 0.0, (2 * i + 1) as f64 * a, (2 * j + 1) as f64 * b);
                disks.push(d);
                grains.push(g);
            }
        }
    }
    (disks, grains)
}

#[test]
fn touching_lattices_pass_and_a_push_into_a_neighbour_is_found() {
    for (outline, a, b) in lattice_shapes() {
        let (nx, ny) = (6, 5);
        let domain = Domain::rectangle(2.0 * a * nx as f64, 2.0 * b * ny as f64).unwrap();
        let (mut disks, grains) = lattice(&outline, (a, b), (nx, ny), |_, _| true);
        let c = check_particles(&disks, &grains, &domain, None);
        assert!(c.valid(), "{outline:?}: {c:?}");
        assert_eq!(c.particles, nx * ny);
        // Every horizontal and vertical neighbour pair touches: proved apart.
        assert!(c.pairs_certified >= (nx - 1) * ny + nx * (ny - 1), "{c:?}");
        assert!(c.porosity > 0.0 && c.porosity < 1.0);

        // Particle 8 (column 2, row 1) pushed 1 % of its length into
        // particle 9.
        disks[8].c.x += 0.01 * 2.0 * a;
        let c = check_particles(&disks, &grains, &domain, None);
        assert_eq!(c.overlaps, 1, "{outline:?}: {c:?}");
        let (i, j, depth) = c.worst_overlap.unwrap();
        assert_eq!((i, j), (8, 9));
        let sum = 2.0 * outline.circumradius();
        assert!(
            depth > 0.2 * 0.02 * a / sum && depth < 1.01 * 0.02 * a / sum,
            "{outline:?}: depth {depth}"
        );
        assert_eq!(c.outside, 0);
    }
}

#[test]
fn turned_lattices_pass_and_a_push_is_found() {
    // The same lattices turned by 0.3 rad about the origin, in a domain
    // wide enough to hold them.
    let turn = 0.3f64;
    let (s, co) = turn.sin_cos();
    for (outline, a, b) in lattice_shapes() {
        let (mut disks, mut grains) = lattice(&outline, (a, b), (5, 5), |_, _| true);
        for (d, g) in disks.iter_mut().zip(&mut grains) {
            d.c = Point::new(
                co * d.c.x - s * d.c.y + 100.0,
                s * d.c.x + co * d.c.y + 100.0,
            );
            g.angle = turn;
        }
        let domain = Domain::rectangle(200.0, 200.0).unwrap();
        let c = check_particles(&disks, &grains, &domain, None);
        assert!(c.valid(), "{outline:?}: {c:?}");
        assert!(c.pairs_certified >= 2 * 4 * 5);
        // Row 1, column 2 pushed 1 % along the turned y axis into row 2.
        let k = 5 + 2;
        disks[k].c += Vector2::new(-s, co) * (0.01 * 2.0 * b);
        let c = check_particles(&disks, &grains, &domain, None);
        assert_eq!(c.overlaps, 1, "{outline:?}: {c:?}");
        let (i, j, _) = c.worst_overlap.unwrap();
        assert_eq!((i, j), (k, k + 5));
    }
}

#[test]
fn a_push_through_a_rectangle_or_an_l_shape_is_outside() {
    for (outline, a, b) in lattice_shapes() {
        let (nx, ny) = (6, 4);
        let (w, h) = (2.0 * a * nx as f64, 2.0 * b * ny as f64);
        let rectangle = Domain::rectangle(w, h).unwrap();
        let l_shape = Domain::polygon(&[
            Point::new(0.0, 0.0),
            Point::new(w, 0.0),
            Point::new(w, h / 2.0),
            Point::new(w / 2.0, h / 2.0),
            Point::new(w / 2.0, h),
            Point::new(0.0, h),
        ])
        .unwrap();
        let in_l = |i: usize, j: usize| i < nx / 2 || j < ny / 2;
        for (domain, keep) in [
            (
                &rectangle,
                &(|_: usize, _: usize| true) as &dyn Fn(usize, usize) -> bool,
            ),
            (&l_shape, &in_l),
        ] {
            let (disks, grains) = lattice(&outline, (a, b), (nx, ny), keep);
            let c = check_particles(&disks, &grains, domain, None);
            assert!(c.valid(), "{outline:?} in {domain:?}: {c:?}");
            // Each particle on the boundary pushed 1 % of its size out
            // through its wall: right, top, left, bottom, and for the L the
            // inner walls (x = w/2 above h/2, y = h/2 right of w/2).
            let centre = |i: usize, j: usize| {
                disks
                    .iter()
                    .position(|d| {
                        (d.c.x - (2 * i + 1) as f64 * a).abs() < 1e-9
                            && (d.c.y - (2 * j + 1) as f64 * b).abs() < 1e-9
                    })
                    .unwrap()
            };
            let mut pushes = vec![
                (centre(0, 1), Vector2::new(-0.02 * a, 0.0)),
                (centre(2, 0), Vector2::new(0.0, -0.02 * b)),
                (centre(nx - 1, 0), Vector2::new(0.02 * a, 0.0)),
                (centre(0, ny - 1), Vector2::new(0.0, 0.02 * b)),
            ];
            if std::ptr::eq(domain, &l_shape) {
                pushes.push((centre(nx / 2 - 1, ny - 1), Vector2::new(0.02 * a, 0.0)));
                pushes.push((centre(nx - 1, ny / 2 - 1), Vector2::new(0.0, 0.02 * b)));
            }
            for (k, by) in pushes {
                let mut moved = disks.clone();
                moved[k].c += by;
                let c = check_particles(&moved, &grains, domain, None);
                assert_eq!(c.outside, 1, "{outline:?} {k} by {by:?}: {c:?}");
                let (i, far) = c.worst_outside.unwrap();
                assert_eq!(i, k);
                assert!(far >= 0.99 * by.norm() && far < 2.0 * by.norm(), "{far}");
                assert_eq!(c.overlaps, 0);
            }
        }
    }
}

/// The farthest distance from O of `outline` with its centre at (`at`, 0)
/// and its own x axis along the x axis, from points on the outline: the
/// farthest corner plus the rounding for a polygon; a scan of the
/// superellipse's parametrisation refined by golden sections (exact but
/// for rounding: the function is smooth at its maximum).
fn farthest_exact(outline: &Outline, at: f64) -> f64 {
    match outline {
        Outline::Polygon {
            vertices, rounding, ..
        } => {
            vertices
                .iter()
                .map(|v| (v.x + at).hypot(v.y))
                .fold(0.0, f64::max)
                + rounding
        }
        Outline::Superellipse { a, b, alpha, beta } => {
            let f = |t: f64| {
                let (s, c) = t.sin_cos();
                (at + a * c.abs().powf(2.0 / alpha)).hypot(b * s.abs().powf(2.0 / beta))
            };
            let n = 10_000;
            let step = FRAC_PI_2 / n as f64;
            let k = (0..=n)
                .max_by(|&i, &j| f(i as f64 * step).total_cmp(&f(j as f64 * step)))
                .unwrap();
            let (mut lo, mut hi) = ((k as f64 - 1.0).max(0.0) * step, (k as f64 + 1.0) * step);
            for _ in 0..100 {
                let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                if f(m1) < f(m2) {
                    lo = m1;
                } else {
                    hi = m2;
                }
            }
            f(0.5 * (lo + hi)).max(f(0.0))
        }
    }
}

#[test]
fn a_push_through_a_circle_is_outside() {
    let o = Point::new(3.0, -2.0);
    for (outline, a, _) in lattice_shapes() {
        // A ring of particles, own x axis along the radius, centres 17 mm
        // from O, in the circle through their farthest points: each
        // touches the wall.
        let at = 17.0;
        let radius = farthest_exact(&outline, at);
        let domain = Domain::circle(o, radius).unwrap();
        let n = 12;
        let place = |k: usize, out: f64| {
            let t = PI * 2.0 * k as f64 / n as f64 + 0.1;
            particle(
                &outline,
                t,
                o.x + (at + out) * t.cos(),
                o.y + (at + out) * t.sin(),
            )
        };
        let (disks, grains): (Vec<Disk>, Vec<Grain>) = (0..n).map(|k| place(k, 0.0)).unzip();
        let c = check_particles(&disks, &grains, &domain, None);
        assert!(c.valid(), "{outline:?}: {c:?}");
        let mut pushed = disks.clone();
        pushed[4] = place(4, 0.02 * a).0;
        let c = check_particles(&pushed, &grains, &domain, None);
        assert_eq!(c.outside, 1, "{outline:?}: {c:?}");
        let (i, far) = c.worst_outside.unwrap();
        assert_eq!(i, 4);
        // An upper bound: the first polygon's slack (7.5·10⁻⁵ of 20 mm) at most.
        let exact = farthest_exact(&outline, at + 0.02 * a) - radius;
        assert!(far >= exact && far < exact + 2e-3, "{far} vs {exact}");
        // Turned a quarter turn, the particles stand back from the wall.
        let side: Vec<Grain> = grains
            .iter()
            .map(|g| Grain::new(g.outline.clone(), g.angle + FRAC_PI_2))
            .collect();
        assert!(check_particles(&disks, &side, &domain, None).valid());
    }
}

#[test]
fn periodic_images_overlap_across_the_edges() {
    for (outline, a, b) in lattice_shapes() {
        let (nx, ny) = (4, 4);
        let cell = Domain::periodic_rectangle(2.0 * a * nx as f64, 2.0 * b * ny as f64).unwrap();
        let (mut disks, grains) = lattice(&outline, (a, b), (nx, ny), |_, _| true);
        let c = check_particles(&disks, &grains, &cell, None);
        assert!(c.valid(), "{outline:?}: {c:?}");
        // Every particle touches four neighbours, across the edges too.
        assert!(c.pairs_certified >= 2 * nx * ny, "{c:?}");
        // The last of the first row pushed 1 % across the right edge, into
        // the image of the first.
        disks[nx - 1].c.x += 0.01 * 2.0 * a;
        let c = check_particles(&disks, &grains, &cell, None);
        assert_eq!(c.overlaps, 1, "{outline:?}: {c:?}");
        let (i, j, _) = c.worst_overlap.unwrap();
        assert_eq!((i, j), (0, nx - 1));
        // Its centre is still in the cell: nothing outside.
        assert_eq!(c.outside, 0);
    }
}

#[test]
fn malformed_particles_are_counted_and_left_out() {
    let e = Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
    let domain = Domain::rectangle(20.0, 20.0).unwrap();
    let (d, g) = particle(&e, 0.0, 5.0, 5.0);
    let bad_outline = Grain::new(
        Outline::Superellipse {
            a: -1.0,
            b: 1.0,
            alpha: 2.0,
            beta: 2.0,
        },
        0.0,
    );
    let disks = vec![d, d, d, Disk::new(f64::NAN, 5.0, 1.0)];
    let grains = vec![
        g.clone(),
        Grain::new(e.clone(), f64::NAN),
        bad_outline,
        g.clone(),
    ];
    let c = check_particles(&disks, &grains, &domain, None);
    assert_eq!((c.particles, c.malformed, c.overlaps), (4, 3, 0));
    // A disk without its grain.
    let c = check_particles(&disks[..2], &grains[..1], &domain, None);
    assert_eq!((c.particles, c.malformed), (2, 1));
    assert!(!c.valid());
}

#[test]
fn grading_is_checked_on_the_sizes_given() {
    // 100 ellipses of aspect 2, least widths spread evenly over 1.5–2.5
    // mm: their area-equivalent diameters, √2 times as large, are not.
    let e = Outline::superellipse(2.0, 1.0, 2.0, 2.0).unwrap();
    let (disks, grains): (Vec<Disk>, Vec<Grain>) = (0..100)
        .map(|k| {
            let o = e.scaled(0.5 * (1.505 + 0.01 * k as f64));
            particle(
                &o,
                0.0,
                5.0 + 10.0 * (k % 10) as f64,
                5.0 + 10.0 * (k / 10) as f64,
            )
        })
        .unzip();
    let domain = Domain::rectangle(100.0, 100.0).unwrap();
    let grading = Grading::uniform(1.5, 2.5, crate::Basis::Number).unwrap();
    let widths: Vec<f64> = grains.iter().map(|g| g.outline.least_width()).collect();
    let sized = check_particles_sized(&disks, &grains, &domain, Some(&grading), &widths);
    assert!(sized.valid() && sized.grading_kept(), "{sized:?}");
    let equivalent = check_particles(&disks, &grains, &domain, Some(&grading));
    assert!(!equivalent.grading_kept(), "{equivalent:?}");
    // A missing size makes its particle malformed.
    let short = check_particles_sized(&disks, &grains, &domain, Some(&grading), &widths[..99]);
    assert_eq!(short.malformed, 1);
}

#[test]
fn with_no_grains_it_is_the_disk_check() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    let domain = Domain::rectangle(30.0, 20.0).unwrap();
    let disks: Vec<Disk> = (0..300)
        .map(|_| {
            Disk::new(
                rng.gen_range(0.0..30.0),
                rng.gen_range(0.0..20.0),
                rng.gen_range(0.05..1.0),
            )
        })
        .collect();
    assert_eq!(
        check_particles(&disks, &[], &domain, None),
        check(&disks, &domain, None)
    );
}

/// A random outline of unit-ish size: a superellipse of aspect 1–5 and
/// exponents 1–10, or a convex polygon of 3–7 corners rounded by 0–0.3.
fn random_outline(rng: &mut impl Rng) -> Outline {
    if rng.r#gen::<bool>() {
        return Outline::superellipse(
            rng.gen_range(1.0..5.0),
            1.0,
            rng.gen_range(1.0..10.0),
            rng.gen_range(1.0..10.0),
        )
        .unwrap();
    }
    for _ in 0..100 {
        let k = rng.gen_range(3..8);
        let mut t: Vec<f64> = (0..k).map(|_| rng.gen_range(0.0..2.0 * PI)).collect();
        t.sort_by(f64::total_cmp);
        let v: Vec<Point> = t
            .iter()
            .map(|t| Point::new(2.0 * t.cos(), 1.5 * t.sin()))
            .collect();
        if let Ok(o) = Outline::polygon(0, &v, rng.gen_range(0.0..0.3))
            && o.area() > 0.5
        {
            return o;
        }
    }
    Outline::superellipse(1.0, 1.0, 2.0, 2.0).unwrap()
}

/// The signed distance of two convex counter-clockwise polygons: their
/// distance when apart (vertex to edge), minus their penetration depth
/// when they overlap (the least overlap of their projections on the
/// edges' normals).
fn polygon_signed_distance(p: &[Vector2<f64>], q: &[Vector2<f64>]) -> f64 {
    let mut depth = f64::INFINITY;
    for (poly, other) in [(p, q), (q, p)] {
        for i in 0..poly.len() {
            let e = poly[(i + 1) % poly.len()] - poly[i];
            if e.norm() == 0.0 {
                continue;
            }
            let n = Vector2::new(e.y, -e.x).normalize();
            let (lo, hi) = poly.iter().fold((f64::MAX, f64::MIN), |(l, h), v| {
                (l.min(n.dot(v)), h.max(n.dot(v)))
            });
            let (lo2, hi2) = other.iter().fold((f64::MAX, f64::MIN), |(l, h), v| {
                (l.min(n.dot(v)), h.max(n.dot(v)))
            });
            depth = depth.min(hi.min(hi2) - lo.max(lo2));
        }
    }
    if depth > 0.0 {
        return -depth;
    }
    let to_segment = |x: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>| {
        let e = b - a;
        let s = ((x - a).dot(&e) / e.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        (x - a - e * s).norm()
    };
    let mut best = f64::INFINITY;
    for (poly, other) in [(p, q), (q, p)] {
        for x in poly {
            for i in 0..other.len() {
                best = best.min(to_segment(*x, other[i], other[(i + 1) % other.len()]));
            }
        }
    }
    best
}

#[test]
fn random_pairs_agree_with_brute_force_polygons() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let domain = Domain::rectangle(100.0, 100.0).unwrap();
    let (mut apart, mut overlapping) = (0, 0);
    for _ in 0..300 {
        let (oa, ob) = (random_outline(&mut rng), random_outline(&mut rng));
        let (ra, rb) = (oa.circumradius(), ob.circumradius());
        let t: f64 = rng.gen_range(0.0..2.0 * PI);
        let dist = (ra + rb) * rng.gen_range(0.15..1.05);
        let (ga, gb) = (
            Grain::new(oa, rng.gen_range(0.0..2.0 * PI)),
            Grain::new(ob, rng.gen_range(0.0..2.0 * PI)),
        );
        let ca = Point::new(50.0, 50.0);
        let cb = ca + Vector2::new(t.cos(), t.sin()) * dist;
        let disks = [
            Disk::new(ca.x, ca.y, ga.outline.equivalent_radius()),
            Disk::new(cb.x, cb.y, gb.outline.equivalent_radius()),
        ];
        let c = check_particles(&disks, &[ga.clone(), gb.clone()], &domain, None);
        let (ta, tb) = (ga.turned(), gb.turned());
        let poly = |g: &Grain, c: Point| -> Vec<Vector2<f64>> {
            let t = g.turned();
            g.outline
                .boundary(400)
                .iter()
                .map(|p| t.to_world(*p) + c.coords)
                .collect()
        };
        let brute = polygon_signed_distance(&poly(&ga, ca), &poly(&gb, cb));
        let sum = ra + rb;
        let tol = OVERLAP_REL * sum;
        let lower = pair_lower(&ta, ca, &tb, cb, tol);
        // The inscribed polygons are no nearer than the particles, and the
        // particles no nearer than the certified bound.
        assert!(
            brute >= lower - 1e-12 * sum,
            "{ga:?} {gb:?}: {brute} < {lower}"
        );
        if c.overlaps == 0 {
            apart += 1;
        } else {
            overlapping += 1;
            let (_, _, depth) = c.worst_overlap.unwrap();
            assert!(depth * sum >= -brute - 1e-12 * sum, "{depth} vs {brute}");
        }
        if brute < -tol {
            assert_eq!(c.overlaps, 1, "{ga:?} {gb:?} overlap by {brute}: {c:?}");
        }
        // Clearly apart (beyond the polygonisation's error): proved apart.
        if brute > 0.02 * sum {
            assert_eq!(c.overlaps, 0, "{ga:?} {gb:?} apart by {brute}: {c:?}");
        }
    }
    assert!(
        apart > 50 && overlapping > 50,
        "{apart} apart, {overlapping} overlapping"
    );
}
