//! Self-consistency of the per-valence eigen tables against their own
//! definition: eigenvalues vs the closed forms, n = 4 vs the bicubic B-spline.
use ccss_core::math::bspline::eval_points as eval_grid;
use ccss_core::mesh::stencil::{label_at, MAX_K};
use ccss_core::{BuildScratch, DVec3, TableSet, ValenceTable, Weights, MAX_VALENCE};

fn tables() -> Box<TableSet> {
    let mut t = Box::new(TableSet::ZERO);
    let mut s = Box::new(BuildScratch::ZERO);
    t.build_into(&Weights::STANDARD, &mut s)
        .expect("tables build");
    t
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64) / ((1u64 << 53) as f64)
}

#[test]
fn all_valences_build_and_eigenvalues_match_closed_forms() {
    let t = tables();
    for n in 3..=MAX_VALENCE {
        let tab: &ValenceTable = t.get(n).unwrap();
        let ev = tab.eigenvalues();
        assert_eq!(ev.len(), 2 * n + 8);
        assert!((ev[0] - 1.0).abs() < 1e-15);
        // subdominant = lambda_2 = (c+5+sqrt((c+1)(c+9)))/16 with c = cos(2 pi/n)
        let c = (2.0 * std::f64::consts::PI / n as f64).cos();
        let l2 = (c + 5.0 + ((c + 1.0) * (c + 9.0)).sqrt()) / 16.0;
        assert!((tab.subdominant() - l2).abs() < 1e-14, "n={n}");
        // limit weights: (n^2 V + 4 sum E + sum F)/(n(n+5))
        let lw = tab.limit_weights();
        let d = (n * (n + 5)) as f64;
        assert!(
            (lw[0] - (n * n) as f64 / d).abs() < 1e-12,
            "n={n} {}",
            lw[0]
        );
        for i in 0..n {
            assert!((lw[1 + 2 * i] - 4.0 / d).abs() < 1e-12);
            assert!((lw[2 + 2 * i] - 1.0 / d).abs() < 1e-12);
        }
        for &w in &lw[2 * n + 1..] {
            assert!(w.abs() < 1e-12);
        }
    }
}

#[test]
fn valence4_table_reproduces_bicubic_bspline() {
    let t = tables();
    let tab = t.get(4).unwrap();
    let mut seed = 7u64;
    let mut pts = [DVec3::ZERO; MAX_K];
    let mut grid = [DVec3::ZERO; 16];
    for y in -1..=2i32 {
        for x in -1..=2i32 {
            let p = DVec3::new(
                x as f64 + 0.3 * lcg(&mut seed),
                y as f64 + 0.3 * lcg(&mut seed),
                lcg(&mut seed),
            );
            pts[label_at(4, x, y).unwrap()] = p;
            grid[((y + 1) * 4 + x + 1) as usize] = p;
        }
    }
    let mut worst = 0.0f64;
    let mut worst1 = 0.0f64;
    let mut worst2 = 0.0f64;
    for i in 0..=40 {
        for j in 0..=40 {
            let (u, v) = (i as f64 / 40.0, j as f64 / 40.0);
            let (u, v) = (u * u, v * v * v); // bias toward the corner
            let a = tab.eval_patch(&pts, u, v, true).unwrap();
            let b = eval_grid::<true>(&grid, u, v);
            worst = worst.max((a.p - b.p).length() / (1.0 + b.p.length()));
            worst = worst.max((a.du - b.du).length() / (1.0 + b.du.length()));
            worst = worst.max((a.dv - b.dv).length() / (1.0 + b.dv.length()));
            worst1 = worst1.max(worst);
            worst = 0.0;
            if u == 0.0 && v == 0.0 {
                continue; // second derivatives are reported as 0 at the EV corner
            }
            worst = worst.max((a.duu - b.duu).length() / (1.0 + b.duu.length()));
            worst = worst.max((a.duv - b.duv).length() / (1.0 + b.duv.length()));
            worst = worst.max((a.dvv - b.dvv).length() / (1.0 + b.dvv.length()));
            worst2 = worst2.max(worst);
            worst = 0.0;
        }
    }
    // Position and first derivatives to rounding; second derivatives lose
    // about log2(1/u) bits near the corner (the linear eigenfunctions' zero
    // second derivative is multiplied by 2^m).
    assert!(worst1 < 1e-13, "position/first derivatives: {worst1}");
    assert!(worst2 < 1e-10, "second derivatives: {worst2}");
}
