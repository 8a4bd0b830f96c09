use super::*;

#[test]
fn output_times_hit_every_interval_and_the_end() {
    assert_eq!(
        output_times(0.2, Some(0.05)),
        vec![0.0, 0.05, 0.1, 0.15000000000000002, 0.2]
    );
    assert_eq!(output_times(1.0, None), vec![0.0, 1.0]);
    assert_eq!(output_times(0.25, Some(0.1)), vec![0.0, 0.1, 0.2, 0.25]);
}

#[test]
fn next_step_lands_exactly_and_leaves_no_sliver() {
    assert_eq!(next_step(1.0, 0.5), (0.5, true));
    assert_eq!(next_step(0.4, 0.5), (0.25, false));
    assert_eq!(next_step(0.1, 0.5), (0.1, false));
}

/// One particle of 2 kg (ρ 2 kg/m³, ppc 1) at x = 1.5 m, the centre of
/// cell 1 of a 1D grid of four 1 m cells, moving at 3 m/s and falling
/// along x under g = −10 m/s², with the given node fields.
fn one_particle(node_fields: &str) -> String {
    format!(
        r#"Scenario(
name: "nodes",
domain: (lower: (0.0, 0.0, 0.0), upper: (4.0, 1.0, 1.0), cells: (4, 1, 1)),
time: (end: 1.0e-4, cfl: 0.4),
materials: {{
    "solid": (model: Hypoelastic(shear_modulus: 3.0e7, pressure: Linear(bulk_modulus: 6.0e7))),
}},
pipeline: Mpm(ppc: 1, gravity: (-10.0, 0.0, 0.0)),
initial: [
    (
        region: Box(min: (1.0, 0.0, 0.0), max: (2.0, 1.0, 1.0)),
        material: "solid",
        state: (density: 2.0, velocity: (3.0, 0.0, 0.0), temperature: 300.0),
    ),
],
outputs: (
    fields: ["density"],
    node_fields: {node_fields},
),
)"#
    )
}

/// The point-data arrays of a `.vti` file, by name.
fn point_arrays(path: &Path) -> Vec<(String, Vec<f64>)> {
    use vtkio::model::{Attribute, DataSet, Piece};
    let vtk = vtkio::Vtk::import(path).unwrap();
    let DataSet::ImageData { pieces, .. } = vtk.data else {
        panic!("not ImageData");
    };
    let Piece::Inline(piece) = pieces.into_iter().next().unwrap() else {
        panic!("piece not inline");
    };
    piece
        .data
        .point
        .into_iter()
        .map(|a| {
            let Attribute::DataArray(a) = a else {
                panic!("not a data array");
            };
            let vtkio::IOBuffer::F64(v) = a.data else {
                panic!("not Float64");
            };
            (a.name, v)
        })
        .collect()
}

#[test]
fn an_mpm_run_writes_node_fields_and_the_work_of_gravity() {
    let text = one_particle(r#"["mass", "velocity_x", "active"]"#);
    let loaded = crate::load_str("nodes.ron", &text, &[]).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let opts = RunOptions {
        out_dir: dir.path().to_path_buf(),
        restart: None,
        progress: false,
    };
    run(&loaded, &opts).unwrap();
    // At t = 0 the particle's mass and momentum go half to node 1 and
    // half to node 2 (linear weights ½ at the cell centre).
    let first = point_arrays(&dir.path().join("vtk/nodes_nodes_00000.vti"));
    assert_eq!(
        first,
        vec![
            ("mass".to_string(), vec![0.0, 1.0, 1.0, 0.0, 0.0]),
            ("velocity_x".to_string(), vec![0.0, 3.0, 3.0, 0.0, 0.0]),
            ("active".to_string(), vec![0.0, 1.0, 1.0, 0.0, 0.0]),
        ]
    );
    // At the end: the nodes of the last step still carry the 2 kg.
    let last = point_arrays(&dir.path().join("vtk/nodes_nodes_00001.vti"));
    assert_eq!(last[0].1.iter().sum::<f64>(), 2.0);
    let pvd = std::fs::read_to_string(dir.path().join("nodes_nodes.pvd")).unwrap();
    assert!(pvd.contains("file=\"vtk/nodes_nodes_00000.vti\""), "{pvd}");
    assert!(pvd.contains("file=\"vtk/nodes_nodes_00001.vti\""), "{pvd}");
    // The particle falls freely: the work of gravity is the kinetic
    // energy it gains, so E − W stays at E(0).
    let (header, rows) = io::read_csv(&dir.path().join("conservation.csv")).unwrap();
    assert_eq!(
        header[5..],
        ["energy", "external_work", "energy_minus_external_work"]
    );
    assert_eq!(rows.len(), 2);
    let (e0, w) = (rows[0][5], rows[1][6]);
    assert_eq!(rows[0][6], 0.0);
    // Speed 3 − 10 t (t = 1e-4 s), from 3: W = ½ m (v² − v0²) < 0.
    let v = 3.0 - 10.0 * 1.0e-4;
    let hand = 0.5 * 2.0 * (v * v - 9.0);
    assert!(
        (w - hand).abs() < 1e-12 * hand.abs(),
        "W = {w}, hand {hand}"
    );
    assert!((rows[1][7] - e0).abs() < 1e-12 * e0, "{rows:?}");
}

/// The cell-data arrays of an ImageData file, or of every piece of a
/// `.pvti` master put back in global x-fastest order, by name.
fn cell_arrays(path: &Path) -> Vec<(String, Vec<f64>)> {
    use vtkio::model::{Attribute, DataSet, Extent, Piece};
    let mut vtk = vtkio::Vtk::import(path).unwrap();
    vtk.load_all_pieces().unwrap();
    let DataSet::ImageData { extent, pieces, .. } = vtk.data else {
        panic!("not ImageData");
    };
    let range = |e: &Extent| -> [(usize, usize); 3] {
        let Extent::Ranges(r) = e else {
            panic!("extent not given as ranges")
        };
        std::array::from_fn(|d| (*r[d].start() as usize, *r[d].end() as usize))
    };
    let whole = range(&extent);
    let n: [usize; 3] = std::array::from_fn(|d| whole[d].1 - whole[d].0);
    let mut out: Vec<(String, Vec<f64>)> = Vec::new();
    for piece in pieces {
        let Piece::Inline(piece) = piece else {
            panic!("piece not loaded");
        };
        let r = range(&piece.extent);
        for (f, a) in piece.data.cell.into_iter().enumerate() {
            let Attribute::DataArray(a) = a else {
                panic!("not a data array");
            };
            let vtkio::IOBuffer::F64(v) = a.data else {
                panic!("not Float64");
            };
            if out.len() == f {
                out.push((a.name.clone(), vec![f64::NAN; n.iter().product()]));
            }
            assert_eq!(out[f].0, a.name);
            let mut values = v.into_iter();
            for k in r[2].0..r[2].1 {
                for j in r[1].0..r[1].1 {
                    for i in r[0].0..r[0].1 {
                        out[f].1[i + n[0] * (j + n[1] * k)] = values.next().unwrap();
                    }
                }
            }
            assert!(values.next().is_none(), "piece {r:?} has too many values");
        }
    }
    out
}

/// The `Patches` layout writes one piece per patch under a `.pvti`
/// master, and the pieces put together hold the bits of the `Whole`
/// layout's file at every output, for the FDM (3D) and the ICE (r–z).
#[test]
fn patch_pieces_put_together_are_the_whole_grid_bit_for_bit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/mpi");
    for (file, name, patches, outputs) in [
        ("blast3d.ron", "blast3d", 8, 5),
        ("ice_rz.ron", "ice_rz", 4, 4),
    ] {
        let dirs = [tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap()];
        for (dir, layout) in dirs.iter().zip(["Whole", "Patches"]) {
            let sets = [
                format!("outputs.vtk_layout={layout}"),
                "outputs.checkpoint_every=None".to_string(),
            ];
            let loaded = crate::load_file(&root.join(file), &sets).unwrap();
            let opts = RunOptions {
                out_dir: dir.path().to_path_buf(),
                restart: None,
                progress: false,
            };
            run(&loaded, &opts).unwrap();
        }
        let pvd = std::fs::read_to_string(dirs[1].path().join(format!("{name}.pvd"))).unwrap();
        for k in 0..outputs {
            let stem = format!("{name}_{k:05}");
            assert!(pvd.contains(&format!("file=\"vtk/{stem}.pvti\"")), "{pvd}");
            let vtk = dirs[1].path().join("vtk");
            let written = std::fs::read_dir(vtk.join(&stem)).unwrap().count();
            assert_eq!(written, patches, "{stem}");
            let whole = cell_arrays(&dirs[0].path().join(format!("vtk/{stem}.vti")));
            let pieces = cell_arrays(&vtk.join(format!("{stem}.pvti")));
            assert_eq!(whole.len(), pieces.len());
            for ((a, va), (b, vb)) in whole.iter().zip(&pieces) {
                assert_eq!(a, b);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(va), bits(vb), "{stem}: {a}");
            }
        }
        assert!(!dirs[1]
            .path()
            .join(format!("vtk/{name}_00000.vti"))
            .exists());
    }
}

#[test]
fn the_patches_layouts_are_refused_where_cells_are_not_in_patches() {
    let text = one_particle("[]");
    let sets = ["outputs.vtk_layout=Patches".to_string()];
    let err = crate::load_str("nodes.ron", &text, &sets).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("outputs.vtk_layout"));
    assert!(
        err.message.contains("only the Fdm, Ice and IceMpm"),
        "{err}"
    );
    let sets = ["outputs.checkpoint_layout=Patches".to_string()];
    let err = crate::load_str("nodes.ron", &text, &sets).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("outputs.checkpoint_layout"));
    assert!(err.message.contains("only the Fdm and Ice"), "{err}");
}

#[test]
fn unknown_node_fields_are_located_in_the_file() {
    let text = one_particle(
        r#"["mass",
        "pressure"]"#,
    );
    let err = crate::load_str("nodes.ron", &text, &[]).unwrap_err();
    let line = text
        .lines()
        .position(|l| l.contains("\"pressure\""))
        .unwrap()
        + 1;
    assert_eq!(err.field.as_deref(), Some("outputs.node_fields.1"));
    assert_eq!(err.position.map(|p| p.0), Some(line));
    let shown = err.to_string();
    assert!(shown.starts_with(&format!("nodes.ron:{line}:")), "{shown}");
    assert!(shown.contains("unknown node field `pressure`"), "{shown}");
    assert!(
        shown.contains("known node fields: mass, momentum_x"),
        "{shown}"
    );

    // The Fdm pipeline has no node grid.
    let sod = include_str!("../../../../configs/sod.ron");
    let err =
        crate::load_str("sod.ron", sod, &["outputs.node_fields=[\"mass\"]".into()]).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("outputs.node_fields"));
    assert!(err.message.contains("only the Mpm pipeline"), "{err}");
}

#[test]
fn lineout_points_are_segment_midpoints() {
    let p = lineout_points([0.0, 0.0, 0.0], [1.0, 2.0, 0.0], 4);
    assert_eq!(p[0], [0.125, 0.25, 0.0]);
    assert_eq!(p[3], [0.875, 1.75, 0.0]);
}
