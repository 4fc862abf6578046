//! The `ccss` command's OBJ reader (lines, tags) on any bytes: no panic;
//! an accepted text gives faces of at least three in-range vertices and
//! finite coordinates, and every error is one line.
#![no_main]
use ccss_cli::io::mesh_in::Mesh;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if data.len() > 4096 {
        return;
    }
    match Mesh::parse("fuzz.obj", data) {
        Ok(m) => {
            let nv = m.num_vertices() as u32;
            assert!(m.face_sizes.iter().all(|&n| n >= 3));
            let corners: usize = m.face_sizes.iter().map(|&n| n as usize).sum();
            assert_eq!(corners, m.indices.len());
            assert!(m.indices.iter().all(|&i| i < nv));
            assert!(m.positions.iter().all(|x| x.is_finite()));
            for v in 0..nv {
                assert!((m.obj_vertex(v) as usize) < m.obj_vertex_lines);
            }
        }
        Err(e) => assert!(!e.message.contains('\n') && !e.message.is_empty()),
    }
});
