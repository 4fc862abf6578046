//! The corner-cell flatness bound (`ValenceTable::corner_flatness`, module
//! `ccss_core::eigen::corner_fit`): over the corner region `[0, 2^-k]^2` of an
//! extraordinary patch, the exact limit surface stays within `E_k` of the
//! affine function `L + corner_affine(w)` the bound is built on. Checked by
//! dense exact evaluation (`eval_patch`) for every valence, standard and
//! general weights (including a complex frequency-0 pair), random control
//! points and levels 0..12; `E_k` never exceeds the radius bound `R_k`, and
//! the tightness (max measured / `E_k`) is reported.
use ccss_core::{BuildScratch, DVec3, TableSet, Weights, MAX_VALENCE};
use ccss_tests::harness::{standard_tables, XorShift};

/// Sample points of the unit corner cell: a 25 x 25 grid, and the same grid
/// shrunk towards the corner by 2^-1 .. 2^-6 (the self-similar regions).
fn samples() -> Vec<(f64, f64)> {
    let mut s = Vec::new();
    let n = 24;
    for shrink in 0..7 {
        let f = 0.5f64.powi(shrink);
        for i in 0..=n {
            for j in 0..=n {
                if shrink > 0 && i <= n / 2 && j <= n / 2 {
                    continue; // covered by the next shrink
                }
                s.push((f * i as f64 / n as f64, f * j as f64 / n as f64));
            }
        }
    }
    s
}

/// Max over valences, meshes and levels of (measured / E_k); panics on a
/// violation.
fn check(tables: &TableSet, label: &str) -> f64 {
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let pts = samples();
    let mut worst = 0.0f64;
    for n in 3..=MAX_VALENCE {
        let tab = tables.get(n).unwrap();
        let k = 2 * n + 8;
        for mesh in 0..2 {
            // A bumpy control net around a valence-n vertex: a cone plus noise.
            let points: Vec<DVec3> = (0..k)
                .map(|_| {
                    DVec3::new(
                        rng.signed(),
                        rng.signed(),
                        0.3 * rng.signed() + 0.2 * mesh as f64,
                    )
                })
                .collect();
            let mut ghat = vec![0.0; 3 * k];
            tab.project(&points, &mut ghat);
            let l = DVec3::new(ghat[0], ghat[1], ghat[2]);
            for level in [0u32, 1, 2, 3, 5, 8, 12] {
                let e = tab.corner_flatness(&ghat, level);
                let r = tab.corner_radius(&ghat, level);
                assert!(e <= r, "{label} n={n} level {level}: E {e:e} > R {r:e}");
                let size = 0.5f64.powi(level as i32);
                let mut meas = 0.0f64;
                for &(a, b) in &pts {
                    let s = tab
                        .eval_patch(&points, a * size, b * size, false)
                        .unwrap()
                        .p;
                    let d = (s - l - tab.corner_affine(&ghat, level, (a, b))).length();
                    meas = meas.max(d);
                }
                let slack = 1e-12 * (l.length() + r);
                assert!(
                    meas <= e + slack,
                    "{label} n={n} mesh {mesh} level {level}: |S - A| = {meas:e} > E_k = {e:e}"
                );
                if e > 1e-12 {
                    worst = worst.max(meas / e);
                }
            }
        }
    }
    worst
}

#[test]
fn corner_flatness_bounds_the_surface_standard_rules() {
    let t = check(standard_tables(), "standard");
    eprintln!("standard rules: max |S - A| / E_k = {t:.3}");
    // Tight enough to be worth having: the measured deviation reaches a
    // good fraction of the bound somewhere.
    assert!(t > 0.2, "bound loose: {t}");
}

#[test]
fn corner_flatness_bounds_the_surface_general_weights() {
    for (label, rule) in [
        ("complex pair (0.5, 0.3, 0.2)", (0.5, 0.3, 0.2)),
        ("heavy centre (0.7, 0.2, 0.1)", (0.7, 0.2, 0.1)),
    ] {
        let mut w = Weights::STANDARD;
        for n in 3..=MAX_VALENCE {
            if n != 4 {
                w.set(n, rule.0, rule.1, rule.2).unwrap();
            }
        }
        let mut tables = Box::new(TableSet::ZERO);
        tables
            .build_into(&w, &mut Box::new(BuildScratch::ZERO))
            .unwrap();
        let t = check(&tables, label);
        eprintln!("{label}: max |S - A| / E_k = {t:.3}");
    }
}
