//! How [`crate::FeatureEvaluator`] stores the control points of its
//! cached B-spline pieces: the quadrants of one split piece are 4 x 4
//! windows into the 5 x 5 control grid of the four (B-spline refinement:
//! two children per direction share three of their four points), which
//! holds 25 points instead of 64 for four quadrants \[OSD\]. Sharing is
//! exact: a block is shared only when the points the windows have in
//! common are equal bit for bit, so every window reads exactly the grid
//! its quadrant was refined to.
//!
//! Layer 5 (with the rest of `eval/`): imports `glam` only.

/// A cached B-spline piece is stored as `index + 1` of its first control
/// point in `grids`, plus `WIDE` when its rows are 5 points apart (a window
/// into a block 5 points wide) rather than 4.
pub const WIDE: u32 = 1 << 29;

/// The B-spline control grids of a split piece's quadrants (None where a
/// quadrant is no B-spline).
pub(super) type Kids = [Option<[glam::DVec3; 16]>; 4];

/// Column and row of quadrant `q`'s 4 x 4 window in the 5 x 5 control
/// grid of the four quadrants together (B-spline refinement: two children
/// per direction share three of their four points; rows along `v`).
const WINDOW_AT: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];

/// A block of control points stored together and the quadrants that are 4
/// x 4 windows into it.
pub(super) struct Packed {
    /// Points per row (4 or 5).
    pub stride: usize,
    /// Points of the block (`stride x rows`).
    pub len: usize,
    /// The points, row by row (`len` of them).
    pub pts: [glam::DVec3; 25],
    /// Per quadrant, the offset of its window's first point in the block.
    pub window: [Option<usize>; 4],
}

/// Calls `emit` with the blocks that hold the B-spline quadrants `kids`:
/// one block (the bounding rectangle of their windows in the 5 x 5 grid)
/// when the points they share are equal bit for bit, else one 4 x 4 block
/// each, so every window reads exactly its quadrant's grid.
pub(super) fn pack(kids: &Kids, mut emit: impl FnMut(&Packed)) {
    let present = || (0..4).filter(|&q| kids[q].is_some());
    let (mut c0, mut r0, mut c1, mut r1) = (1, 1, 0, 0);
    for q in present() {
        let (c, r) = WINDOW_AT[q];
        (c0, r0, c1, r1) = (c0.min(c), r0.min(r), c1.max(c), r1.max(r));
    }
    if c0 > c1 {
        return;
    }
    let (w, h) = (c1 - c0 + 4, r1 - r0 + 4);
    let mut block = Packed {
        stride: w,
        len: w * h,
        pts: [glam::DVec3::ZERO; 25],
        window: [None; 4],
    };
    let mut set = [false; 25];
    let bits = |p: glam::DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut shared = true;
    for q in present() {
        let (c, r) = WINDOW_AT[q];
        let at = (r - r0) * w + (c - c0);
        let g = kids[q].as_ref().expect("present");
        for (k, &p) in g.iter().enumerate() {
            let i = at + (k / 4) * w + k % 4;
            if set[i] && bits(block.pts[i]) != bits(p) {
                shared = false;
            }
            block.pts[i] = p;
            set[i] = true;
        }
        block.window[q] = Some(at);
    }
    if shared {
        emit(&block);
        return;
    }
    for q in present() {
        let mut one = Packed {
            stride: 4,
            len: 16,
            pts: [glam::DVec3::ZERO; 25],
            window: [None; 4],
        };
        one.pts[..16].copy_from_slice(kids[q].as_ref().expect("present"));
        one.window[q] = Some(0);
        emit(&one);
    }
}

/// Stores a block of control points (rows `stride` points apart) at point
/// `*next` of `grids` and moves `*next` past it; the code (see [`WIDE`]) of
/// the window that starts at point `at` of the block.
pub(super) fn put(
    pts: &[glam::DVec3],
    stride: usize,
    grids: &mut [f64],
    next: &mut usize,
) -> impl Fn(usize) -> u32 {
    let first = *next;
    for (i, q) in pts.iter().enumerate() {
        grids[3 * (first + i)..3 * (first + i) + 3].copy_from_slice(&[q.x, q.y, q.z]);
    }
    *next += pts.len();
    let wide = if stride == 5 { WIDE } else { 0 };
    move |at: usize| (first + at + 1) as u32 | wide
}

/// Bits of a [`block_hint`] that hold the block's first point + 1 (the
/// four bits above them say which quadrants are windows into it).
const HINT_POINT: u32 = (1 << 28) - 1;

/// Where the B-spline quadrants of a node group lie, from their codes (see
/// [`WIDE`]; `codes[q]` is `None` where quadrant `q` is no B-spline
/// window): the first point of their shared block + 1, and above it
/// ([`HINT_POINT`]) the quadrants that are windows into it; 0 when they
/// are not windows of one block (or the block starts beyond the bits).
/// Kept beside the tree entry that leads to the group, so a query can ask
/// for its window's cache lines while it still reads the group's entry.
pub(super) fn block_hint(codes: [Option<u32>; 4]) -> u32 {
    let mask = (0..4)
        .filter(|&q| codes[q].is_some())
        .fold(0, |m, q| m | 1 << q);
    let Some((c0, r0, w)) = rect_of(mask) else {
        return 0;
    };
    let mut start = None;
    for (q, code) in codes.iter().enumerate() {
        let Some(code) = *code else { continue };
        let (c, r) = WINDOW_AT[q];
        let at = (r - r0) * w + (c - c0);
        let first = (code & (WIDE - 1)) as usize - 1;
        if (code & WIDE != 0) != (w == 5) || first < at || start.is_some_and(|s| s != first - at) {
            return 0;
        }
        start = Some(first - at);
    }
    match start {
        Some(s) if s < HINT_POINT as usize => (s + 1) as u32 | mask << 28,
        _ => 0,
    }
}

/// The first point of quadrant `q`'s window, from a [`block_hint`];
/// `None` when `q` is not a window of the hinted block.
#[inline(always)]
pub(super) fn hinted_window(hint: u32, q: usize) -> Option<usize> {
    if hint >> (28 + q) & 1 == 0 {
        return None;
    }
    let at = WINDOW_OFFSET[(hint >> 28) as usize][q] as usize;
    Some((hint & HINT_POINT) as usize - 1 + at)
}

/// Per set of quadrants (bit `q`: quadrant `q`) and quadrant, the offset
/// of its window in the block [`pack`] stores them in (the bounding
/// rectangle of their windows in the 5 x 5 grid).
const WINDOW_OFFSET: [[u8; 4]; 16] = {
    let mut t = [[0; 4]; 16];
    let mut mask = 1;
    while mask < 16 {
        if let Some((c0, r0, w)) = rect_of(mask as u32) {
            let mut q = 0;
            while q < 4 {
                let (c, r) = WINDOW_AT[q];
                if c >= c0 && r >= r0 {
                    t[mask][q] = ((r - r0) * w + (c - c0)) as u8;
                }
                q += 1;
            }
        }
        mask += 1;
    }
    t
};

/// Left column, top row and width of the bounding rectangle (in the 5 x 5
/// grid) of the windows of the quadrants in `mask` (bit `q`: quadrant `q`),
/// as [`pack`] stores them; `None` for no quadrant.
const fn rect_of(mask: u32) -> Option<(usize, usize, usize)> {
    if mask & 15 == 0 {
        return None;
    }
    let (mut c0, mut r0, mut c1) = (1, 1, 0);
    let mut q = 0;
    while q < 4 {
        if mask >> q & 1 == 1 {
            let (c, r) = WINDOW_AT[q];
            c0 = if c < c0 { c } else { c0 };
            r0 = if r < r0 { r } else { r0 };
            c1 = if c > c1 { c } else { c1 };
        }
        q += 1;
    }
    Some((c0, r0, c1 - c0 + 4))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// The 4 x 4 window at `(c, r)` of a 5 x 5 grid.
    fn window(g: &[DVec3; 25], c: usize, r: usize) -> [DVec3; 16] {
        core::array::from_fn(|k| g[(r + k / 4) * 5 + c + k % 4])
    }

    /// What a window of a stored block reads (as the evaluator does).
    fn read(b: &Packed, at: usize) -> [DVec3; 16] {
        core::array::from_fn(|k| b.pts[at + (k / 4) * b.stride + k % 4])
    }

    fn grid5() -> [DVec3; 25] {
        core::array::from_fn(|i| DVec3::new(i as f64, (i * i) as f64 * 0.1, -(i as f64)))
    }

    fn packed(kids: &Kids) -> ([usize; 2], [Option<[DVec3; 16]>; 4]) {
        let (mut blocks, mut points) = (0, 0);
        let mut got = [None; 4];
        pack(kids, |b| {
            blocks += 1;
            points += b.len;
            for (q, at) in b.window.iter().enumerate() {
                if let Some(at) = *at {
                    assert!(got[q].is_none());
                    got[q] = Some(read(b, at));
                }
            }
        });
        ([blocks, points], got)
    }

    #[test]
    fn windows_of_one_grid_share_it_and_read_back_exactly() {
        let g = grid5();
        let all: Kids = core::array::from_fn(|q| Some(window(&g, WINDOW_AT[q].0, WINDOW_AT[q].1)));
        // Every subset of quadrants: one block (the bounding rectangle).
        for mask in 1..16usize {
            let kids: Kids =
                core::array::from_fn(|q| (mask >> q & 1 == 1).then(|| all[q].unwrap()));
            let n = mask.count_ones();
            let ([blocks, points], got) = packed(&kids);
            assert_eq!(blocks, 1, "mask {mask}");
            let present = (0..4).filter(|&q| mask >> q & 1 == 1);
            let cols = present.clone().map(|q| WINDOW_AT[q].0);
            let rows = present.map(|q| WINDOW_AT[q].1);
            let w = 4 + cols.clone().max().unwrap() - cols.min().unwrap();
            let h = 4 + rows.clone().max().unwrap() - rows.min().unwrap();
            assert_eq!(points, w * h, "mask {mask}");
            assert!(points <= 16 * n as usize);
            assert_eq!(got, kids, "mask {mask}");
        }
    }

    /// Stores the blocks of `kids` as the evaluator does and returns the
    /// code of each quadrant's window.
    fn codes(kids: &Kids, grids: &mut [f64], next: &mut usize) -> [Option<u32>; 4] {
        let mut codes = [None; 4];
        pack(kids, |b| {
            let code = put(&b.pts[..b.len], b.stride, grids, next);
            for (q, at) in b.window.iter().enumerate() {
                if let Some(at) = *at {
                    codes[q] = Some(code(at));
                }
            }
        });
        codes
    }

    #[test]
    fn a_hint_names_the_first_point_of_every_window_it_claims() {
        let g = grid5();
        let all: Kids = core::array::from_fn(|q| Some(window(&g, WINDOW_AT[q].0, WINDOW_AT[q].1)));
        let mut grids = [0.0; 3 * 100];
        let mut hinted = 0;
        for shared in [true, false] {
            for mask in 1..16usize {
                let mut kids: Kids =
                    core::array::from_fn(|q| (mask >> q & 1 == 1).then(|| all[q].unwrap()));
                if !shared {
                    // Every quadrant's last point differs: separate blocks.
                    for k in kids.iter_mut().flatten() {
                        k[15].x += 0.5;
                    }
                }
                // Blocks start after a few points, as in a real cache.
                let mut next = 7;
                let codes = codes(&kids, &mut grids, &mut next);
                let hint = block_hint(codes);
                for (q, code) in codes.iter().enumerate() {
                    let first = code.map(|c| (c & (WIDE - 1)) as usize - 1);
                    match hinted_window(hint, q) {
                        Some(at) => {
                            assert_eq!(Some(at), first, "mask {mask} q {q}");
                            hinted += 1;
                        }
                        // Only separate blocks (or a missing quadrant) go
                        // without a hint.
                        None => assert!(first.is_none() || !shared || hint == 0, "mask {mask}"),
                    }
                }
                if shared {
                    assert_ne!(hint, 0, "mask {mask}");
                }
            }
        }
        // Shared blocks: one hint per window (32 over the 15 masks).
        assert!(hinted >= 32, "{hinted}");
        assert_eq!(block_hint([None; 4]), 0);
    }

    #[test]
    fn a_shared_point_that_differs_in_one_bit_keeps_the_grids_apart() {
        let g = grid5();
        let mut kids: Kids =
            core::array::from_fn(|q| Some(window(&g, WINDOW_AT[q].0, WINDOW_AT[q].1)));
        // Point (1, 1) of the 5 x 5 grid is in every window; quadrant 2
        // (window at (1, 1)) has it first.
        let p = &mut kids[2].as_mut().unwrap()[0];
        p.y = f64::from_bits(p.y.to_bits() ^ 1);
        let ([blocks, points], got) = packed(&kids);
        assert_eq!([blocks, points], [4, 64]);
        assert_eq!(got, kids);
        // Signed zeros are different bits, too.
        let mut zeros: Kids = [None; 4];
        zeros[0] = Some([DVec3::ZERO; 16]);
        zeros[1] = Some([DVec3::new(-0.0, 0.0, 0.0); 16]);
        assert_eq!(packed(&zeros).0, [2, 32]);
        assert_eq!(packed(&[None; 4]).0, [0, 0]);
    }
}
