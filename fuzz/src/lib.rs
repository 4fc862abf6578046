//! What the fuzz targets share: the input layout, the per-input caps and
//! the objects every target builds (tables once per process, topology,
//! evaluator).
//!
//! Input layout (all targets but `obj`, which reads the whole input as an
//! OBJ text): a [`HEADER`]-byte parameter block, then an OBJ text read by
//! the `ccss` command's own reader (`ccss_cli::io::mesh_in::Mesh::parse`).
//! Header byte 0 scales the mesh by `2^(8 * (byte as i8))` (0: unchanged),
//! byte 1 shifts it by `+-10^(byte % 16)` in x (0: unchanged), bytes 2..8
//! are the target's own parameters, bytes 8..16 seed the generator of its
//! queries ([`Rng`]). Seeds (`fuzz/seed.sh`) are the corpus shapes of
//! `tests/data/osd` behind a zero header.

use ccss_cli::io::mesh_in::Mesh;
use ccss_core::mem::words_for;
use ccss_core::{BuildScratch, Evaluator, MeshInput, TableSet, Topology, Weights};
use std::sync::OnceLock;

/// Bytes of the parameter block in front of the OBJ text.
pub const HEADER: usize = 16;

/// Per-input caps on the mesh (larger inputs are skipped, not errors), so
/// that every target runs at least 1000 inputs per second.
#[derive(Clone, Copy, Debug)]
pub struct Caps {
    /// Most faces.
    pub faces: usize,
    /// Most face corners (sum of the face sizes).
    pub corners: usize,
}

/// The caps of the cheap targets (topology, evaluator, eval).
pub const CAPS: Caps = Caps {
    faces: 64,
    corners: 256,
};

/// SplitMix64: the queries of one input, from its header.
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// A number below `n` (`n > 0`).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }
    /// A parameter in `[0, 1]`, now and then one of the ends exactly.
    pub fn unit(&mut self) -> f64 {
        match self.below(8) {
            0 => 0.0,
            1 => 1.0,
            _ => (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
        }
    }
    /// Any `f64` bit pattern one time in 16 (NaN, infinities, huge,
    /// subnormal), else a parameter in `[-0.25, 1.25]`.
    pub fn param(&mut self) -> f64 {
        if self.below(16) == 0 {
            f64::from_bits(self.next_u64())
        } else {
            1.5 * self.unit() - 0.25
        }
    }
}

/// One fuzz input: header and mesh.
pub struct Input {
    /// The parameter block (zero-padded).
    pub header: [u8; HEADER],
    /// The mesh, scaled and shifted as the header says.
    pub mesh: Mesh,
    /// Largest coordinate magnitude after scaling.
    pub max_abs: f64,
}

impl Input {
    /// Parses `data` (see the module docs); `None` when the OBJ text does
    /// not parse or the mesh is beyond `caps`.
    pub fn parse(data: &[u8], caps: Caps) -> Option<Input> {
        let mut header = [0u8; HEADER];
        let n = data.len().min(HEADER);
        header[..n].copy_from_slice(&data[..n]);
        let mut mesh = Mesh::parse("fuzz.obj", &data[n..]).ok()?;
        if mesh.num_faces() > caps.faces || mesh.indices.len() > caps.corners {
            return None;
        }
        if header[0] != 0 {
            let s = 2f64.powi(8 * (header[0] as i8) as i32);
            mesh.positions.iter_mut().for_each(|c| *c *= s);
        }
        if header[1] != 0 {
            let t = 10f64.powi((header[1] % 16) as i32);
            let t = if header[1] & 16 != 0 { -t } else { t };
            mesh.positions.iter_mut().step_by(3).for_each(|c| *c += t);
        }
        let max_abs = mesh.positions.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        Some(Input {
            header,
            mesh,
            max_abs,
        })
    }

    /// The query generator of this input (header bytes 8..16).
    pub fn rng(&self) -> Rng {
        let mut s = [0u8; 8];
        s.copy_from_slice(&self.header[8..16]);
        Rng(u64::from_le_bytes(s))
    }

    /// The mesh as core input.
    pub fn input(&self) -> MeshInput<'_> {
        self.mesh.input()
    }

    /// True when results must be finite numbers: every coordinate within
    /// the certified range of the bounds (`2^-200..2^200`, with room for
    /// the derivatives' factors).
    pub fn tame(&self) -> bool {
        self.max_abs < 1e50
    }
}

/// Zeroed 8-byte words for `bytes` bytes.
pub fn words(bytes: usize) -> Vec<u64> {
    vec![0u64; words_for(bytes)]
}

/// The standard eigen tables, built once per process.
pub fn tables() -> &'static TableSet {
    static T: OnceLock<&'static TableSet> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = Box::new(TableSet::ZERO);
        let mut s = Box::new(BuildScratch::ZERO);
        t.build_into(&Weights::STANDARD, &mut s)
            .expect("standard tables");
        Box::leak(t)
    })
}

/// Builds the topology of `mesh` in `mem` (sized here); `None` when the
/// core refuses the mesh (a named error is the expected outcome).
pub fn topology<'m>(mesh: MeshInput<'m>, mem: &'m mut Vec<u64>) -> Option<Topology<'m>> {
    let nv = mesh.positions.len() / 3;
    *mem = words(Topology::required_bytes(nv, mesh.face_sizes));
    Topology::build(mesh, mem).ok()
}

/// Builds the smooth evaluator of `topo` with the standard tables in `mem`.
pub fn evaluator<'m>(topo: &Topology, mem: &'m mut Vec<u64>) -> Option<Evaluator<'m>> {
    let t = tables();
    let bytes = Evaluator::required_bytes(topo, t).ok()?;
    *mem = words(bytes);
    Evaluator::build(topo, t, mem).ok()
}

/// Asserts that every number is finite.
pub fn assert_finite(what: &str, xs: &[f64]) {
    assert!(
        xs.iter().all(|x| x.is_finite()),
        "{what}: non-finite result {xs:?}"
    );
}
