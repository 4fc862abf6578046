//! Adaptive tessellation through the ABI.

use super::*;

#[test]
fn tessellate_through_the_abi_without_allocating() {
    let (p, s, i) = cube();
    let (mut tb, mut gb, mut eb, mut nb) = (0usize, 0usize, 0usize, 0usize);
    let mut d = Failure::invalid("x").to_detail();
    let opts = CcssTessellationOptions {
        criterion: 0,
        tolerance: 1e-3,
        uniform_level: 0,
        max_level: 0,
    };
    unsafe {
        assert_eq!(
            ccss_tables_required_bytes(&mut tb, ptr::null_mut()),
            CcssStatus::OK
        );
        assert_eq!(
            ccss_topology_required_bytes(8, s.as_ptr(), 6, &mut gb, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    let (mut tm, mut gm) = (block(tb), block(gb));
    let (mut tables, mut topo, mut ev) = (ptr::null(), ptr::null(), ptr::null());
    let mut tess: *mut CcssTessellation = ptr::null_mut();
    unsafe {
        assert_eq!(
            ccss_tables_build_standard(tm.as_mut_ptr().cast(), tb, &mut tables, ptr::null_mut()),
            CcssStatus::OK
        );
        let st = ccss_topology_build(
            p.as_ptr(),
            8,
            s.as_ptr(),
            6,
            i.as_ptr(),
            24,
            gm.as_mut_ptr().cast(),
            gb,
            &mut topo,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_evaluator_required_bytes(topo, tables, &mut eb, &mut d),
            CcssStatus::OK
        );
    }
    let mut em = block(eb);
    unsafe {
        let st = ccss_evaluator_build(topo, tables, em.as_mut_ptr().cast(), eb, &mut ev, &mut d);
        assert_eq!(st, CcssStatus::OK);
    }
    // Size query, then a too-small block reports the same exact size.
    unsafe {
        assert_eq!(
            ccss_tessellation_required_bytes(topo, ev, &opts, &mut nb, &mut d),
            CcssStatus::OK
        );
    }
    let mut small = block(nb - 8);
    let st = unsafe {
        ccss_tessellation_build(
            topo,
            ev,
            &opts,
            small.as_mut_ptr().cast(),
            nb - 8,
            &mut tess,
            &mut d,
        )
    };
    assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
    assert_eq!(d.required as usize, nb);
    assert!(tess.is_null());
    let mut nm = block(nb);
    let mut c = CcssTessellationCountsInfo::default();
    unsafe {
        let st = ccss_tessellation_build(
            topo,
            ev,
            &opts,
            nm.as_mut_ptr().cast(),
            nb,
            &mut tess,
            &mut d,
        );
        assert_eq!(st, CcssStatus::OK);
        assert_eq!(
            ccss_tessellation_counts(tess, &mut c, ptr::null_mut()),
            CcssStatus::OK
        );
    }
    assert!(c.bound <= 1e-3 && c.polygons > 0 && c.triangles == c.polygon_indices - 2 * c.polygons);
    let mut pos = vec![0.0; 3 * c.vertices];
    let mut sizes = vec![0u32; c.polygons];
    let mut idx = vec![0u32; c.polygon_indices];
    let mut tri = vec![0u32; 3 * c.triangles];
    let mut cells = vec![CcssTessellationCell::default(); c.polygons];
    let mut o = CcssTessellationOutput {
        positions: pos.as_mut_ptr(),
        positions_len: pos.len(),
        normals: ptr::null_mut(),
        normals_len: 0,
        params: ptr::null_mut(),
        params_len: 0,
        polygon_sizes: sizes.as_mut_ptr(),
        polygon_sizes_len: sizes.len(),
        polygon_indices: idx.as_mut_ptr(),
        polygon_indices_len: idx.len(),
        triangles: tri.as_mut_ptr(),
        triangles_len: tri.len(),
        cells: cells.as_mut_ptr(),
        cells_len: cells.len(),
    };
    let before = alloc_count::get();
    let mut level = 0u32;
    unsafe {
        assert_eq!(ccss_tessellation_emit(tess, &o, &mut d), CcssStatus::OK);
        assert_eq!(
            ccss_tessellation_uniform_depth(ev, &opts, c.max_level, &mut level, &mut d),
            CcssStatus::OK
        );
    }
    assert_eq!(alloc_count::get(), before, "emission allocated");
    assert!(level >= c.max_level && level != u32::MAX);
    assert_eq!(
        sizes.iter().map(|&x| x as usize).sum::<usize>(),
        c.polygon_indices
    );
    assert!(cells.iter().all(|x| x.level <= c.max_level && x.face < 6));
    // Errors write nothing and name the problem.
    o.triangles_len -= 1;
    let st = unsafe { ccss_tessellation_emit(tess, &o, &mut d) };
    assert_eq!(st, CcssStatus::ERR_BUFFER_TOO_SMALL);
    assert_eq!(d.required as usize, 3 * c.triangles);
    o.triangles_len += 1;
    o.cells = idx.as_mut_ptr().cast();
    let st = unsafe { ccss_tessellation_emit(tess, &o, &mut d) };
    assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT);
    o.cells = ptr::null_mut();
    o.positions = ptr::null_mut();
    let st = unsafe { ccss_tessellation_emit(tess, &o, &mut d) };
    assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
    for bad in [
        CcssTessellationOptions {
            criterion: 7,
            ..opts
        },
        CcssTessellationOptions {
            tolerance: -1.0,
            ..opts
        },
        CcssTessellationOptions {
            tolerance: f64::NAN,
            ..opts
        },
        CcssTessellationOptions {
            max_level: 31,
            ..opts
        },
        CcssTessellationOptions {
            tolerance: 1e-300,
            max_level: 3,
            ..opts
        },
    ] {
        let st = unsafe { ccss_tessellation_required_bytes(topo, ev, &bad, &mut nb, &mut d) };
        assert_eq!(st, CcssStatus::ERR_INVALID_ARGUMENT, "{bad:?}");
    }
    let st = unsafe { ccss_tessellation_counts(ptr::null(), &mut c, ptr::null_mut()) };
    assert_eq!(st, CcssStatus::ERR_NULL_POINTER);
}
