//! VTK XML ImageData (`.vti`) snapshots of cell-centred fields
//! ([`write_vti`]) and of node fields ([`write_vti_nodes`]), and the
//! per-patch layout: one `.vti` piece per patch ([`write_vti_piece`])
//! under a parallel ImageData (`.pvti`) master ([`write_pvti`]) that
//! ParaView opens as one dataset.
//!
//! The file is built and serialised with `vtkio`; every field becomes a
//! one-component `Float64` cell-data (or point-data) array stored inline as base64 binary
//! (little-endian, `UInt64` headers), as VTK's own reader (and so
//! ParaView) expects.

use std::path::Path;

use brisance_core::{CellData, CellPiece, NodeData, UniformGridGeometry};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, DataArray, DataSet, ElementType, Extent, ImageDataPiece,
    Piece, Version,
};
use vtkio::{IOBuffer, Vtk};

use crate::atomic::write_atomic;
use crate::number::format_f64;
use crate::IoError;

/// Writes `data` as a VTK XML ImageData file at `path` (atomically).
///
/// The whole extent is `0 nx 0 ny 0 nz` (points), origin and spacing are
/// those of `data.geometry`, and each `(name, values)` field is a `Float64`
/// cell-data array named `name` whose values are taken in the given
/// x-fastest order. Fails without writing if a field does not have exactly
/// one value per cell.
pub fn write_vti(path: &Path, data: &CellData) -> Result<(), IoError> {
    let layout = Layout {
        origin: data.geometry.origin,
        spacing: data.geometry.spacing,
        lo: [0; 3],
        counts: data.geometry.cells,
        what: "cells",
        on_points: false,
    };
    let bytes = encode_vti(path, &layout, &data.fields)?;
    write_atomic(path, &bytes)
}

/// Writes one patch's cells of a grid as a VTK XML ImageData file at
/// `path` (atomically), as a piece of a [`write_pvti`] master: the whole
/// extent (and the piece's) is the patch's, `lo .. lo + cells` in the
/// points of the whole grid, and origin and spacing are the whole grid's,
/// so the piece lands where it belongs when read alone or through the
/// master. Fails without writing if a field does not have one value per
/// cell of the piece.
pub fn write_vti_piece(
    path: &Path,
    geometry: &UniformGridGeometry,
    piece: &CellPiece,
) -> Result<(), IoError> {
    let layout = Layout {
        origin: geometry.origin,
        spacing: geometry.spacing,
        lo: piece.lo,
        counts: piece.cells,
        what: "cells",
        on_points: false,
    };
    let bytes = encode_vti(path, &layout, &piece.fields)?;
    write_atomic(path, &bytes)
}

/// The text of the parallel ImageData (`.pvti`) master of a per-patch
/// cell output: the whole extent of `geometry`, the `Float64` cell arrays
/// `names`, and one `Piece` per `(lo, cells)` extent whose file is the
/// matching entry of `sources` (paths relative to the master's folder,
/// XML-escaped here).
pub fn pvti_text(
    geometry: &UniformGridGeometry,
    names: &[String],
    extents: &[([usize; 3], [usize; 3])],
    sources: &[String],
) -> String {
    let range = |lo: [usize; 3], n: [usize; 3]| {
        (0..3)
            .map(|d| format!("{} {}", lo[d], lo[d] + n[d]))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut xml = format!(
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
         \x20 <PImageData WholeExtent=\"{}\" GhostLevel=\"0\" Origin=\"{}\" Spacing=\"{}\">\n\
         \x20   <PCellData>\n",
        range([0; 3], geometry.cells),
        geometry.origin.map(format_f64).join(" "),
        geometry.spacing.map(format_f64).join(" "),
    );
    for name in names {
        xml.push_str(&format!(
            "      <PDataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"1\"/>\n",
            crate::pvd::escape_attribute(name)
        ));
    }
    xml.push_str("    </PCellData>\n");
    for (&(lo, n), source) in extents.iter().zip(sources) {
        xml.push_str(&format!(
            "    <Piece Extent=\"{}\" Source=\"{}\"/>\n",
            range(lo, n),
            crate::pvd::escape_attribute(source)
        ));
    }
    xml.push_str("  </PImageData>\n</VTKFile>\n");
    xml
}

/// Writes [`pvti_text`] to `path` (atomically). Fails without writing if
/// there is not one source per extent, or if the extents do not tile the
/// whole grid (every cell in exactly one piece).
pub fn write_pvti(
    path: &Path,
    geometry: &UniformGridGeometry,
    names: &[String],
    extents: &[([usize; 3], [usize; 3])],
    sources: &[String],
) -> Result<(), IoError> {
    if extents.len() != sources.len() {
        return Err(IoError::invalid_input(
            path,
            format!(
                "{} piece extents but {} piece files",
                extents.len(),
                sources.len()
            ),
        ));
    }
    let inside = extents
        .iter()
        .all(|(lo, n)| (0..3).all(|d| n[d] > 0 && lo[d] + n[d] <= geometry.cells[d]));
    let covered: usize = extents
        .iter()
        .map(|(_, n)| n.iter().product::<usize>())
        .sum();
    let overlap = extents.iter().enumerate().any(|(a, (la, na))| {
        extents[a + 1..]
            .iter()
            .any(|(lb, nb)| (0..3).all(|d| la[d] < lb[d] + nb[d] && lb[d] < la[d] + na[d]))
    });
    if !inside || overlap || covered != geometry.cell_count() {
        return Err(IoError::invalid_input(
            path,
            format!(
                "the {} piece extents do not tile the {:?} cells of the grid",
                extents.len(),
                geometry.cells
            ),
        ));
    }
    write_atomic(
        path,
        pvti_text(geometry, names, extents, sources).as_bytes(),
    )
}

/// Writes node fields as a VTK XML ImageData file of point data at `path`
/// (atomically).
///
/// The whole extent is `0 nx−1 0 ny−1 0 nz−1` with nx, ny, nz the node
/// counts, so point (i, j, k) of the file is node (i, j, k) at
/// `origin + (i, j, k) · spacing`; each `(name, values)` field is a
/// `Float64` point-data array named `name`, values in x-fastest order.
/// Fails without writing if a field does not have exactly one value per
/// node.
pub fn write_vti_nodes(path: &Path, data: &NodeData) -> Result<(), IoError> {
    let layout = Layout {
        origin: data.origin,
        spacing: data.spacing,
        lo: [0; 3],
        counts: data.nodes,
        what: "nodes",
        on_points: true,
    };
    let bytes = encode_vti(path, &layout, &data.fields)?;
    write_atomic(path, &bytes)
}

/// Where the values of an ImageData file live.
struct Layout {
    origin: [f64; 3],
    spacing: [f64; 3],
    /// Index of the first cell (or point) in the whole grid.
    lo: [usize; 3],
    /// Cells (cell data) or points (point data) per direction.
    counts: [usize; 3],
    /// `cells` or `nodes`, for messages.
    what: &'static str,
    /// Point data (one value per point) instead of cell data.
    on_points: bool,
}

/// The bytes of the `.vti` file for `fields` on `layout`; `path` only
/// names the target in errors.
fn encode_vti(
    path: &Path,
    layout: &Layout,
    fields: &[(String, Vec<f64>)],
) -> Result<Vec<u8>, IoError> {
    let what = layout.what;
    let count: usize = layout.counts.iter().product();
    let mut lower = [0i32; 3];
    let mut upper = [0i32; 3];
    for d in 0..3 {
        let n = layout.counts[d];
        let max = if layout.on_points {
            i32::MAX as usize + 1
        } else {
            i32::MAX as usize
        };
        let lo = layout.lo[d];
        if n == 0 || n > max {
            return Err(IoError::invalid_input(
                path,
                format!("grid has {n} {what} in direction {d}; VTK needs 1 to {max}"),
            ));
        }
        if lo > max - n {
            return Err(IoError::invalid_input(
                path,
                format!("a piece of {n} {what} from index {lo} in direction {d} ends beyond VTK's {max}"),
            ));
        }
        // Points run lo ..= lo + n − 1; cells lo .. lo + n, whose points
        // run lo ..= lo + n.
        lower[d] = lo as i32;
        upper[d] = (lo + if layout.on_points { n - 1 } else { n }) as i32;
    }
    let mut arrays = Vec::with_capacity(fields.len());
    for (name, values) in fields {
        if values.len() != count {
            return Err(IoError::invalid_input(
                path,
                format!(
                    "field `{name}` has {} values but the grid has {count} {what}",
                    values.len()
                ),
            ));
        }
        arrays.push(Attribute::DataArray(DataArray {
            name: name.clone(),
            elem: ElementType::Generic(1),
            data: IOBuffer::F64(values.clone()),
        }));
    }
    let (point, cell) = if layout.on_points {
        (arrays, Vec::new())
    } else {
        (Vec::new(), arrays)
    };
    let extent = Extent::Ranges(std::array::from_fn(|d| lower[d]..=upper[d]));
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::ImageData {
            extent: extent.clone(),
            // vtkio stores these as f32; the exact f64 text is patched in
            // below.
            origin: layout.origin.map(|x| x as f32),
            spacing: layout.spacing.map(|x| x as f32),
            meta: None,
            pieces: vec![Piece::Inline(Box::new(ImageDataPiece {
                extent,
                data: Attributes { point, cell },
            }))],
        },
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes)
        .map_err(|e| IoError::encode(path, e.to_string()))?;
    let text = String::from_utf8(bytes).map_err(|e| IoError::encode(path, e.to_string()))?;
    let text = replace_attribute(path, &text, "Origin", layout.origin)?;
    let text = replace_attribute(path, &text, "Spacing", layout.spacing)?;
    Ok(text.into_bytes())
}

/// Replaces the value of the first ` name="..."` attribute in `xml` (the
/// one on the `ImageData` element) with the exact text of `v`.
fn replace_attribute(path: &Path, xml: &str, name: &str, v: [f64; 3]) -> Result<String, IoError> {
    let key = format!(" {name}=\"");
    let start = xml
        .find(&key)
        .map(|i| i + key.len())
        .ok_or_else(|| IoError::encode(path, format!("vtkio wrote no {name} attribute")))?;
    let len = xml[start..]
        .find('"')
        .ok_or_else(|| IoError::encode(path, format!("unterminated {name} attribute")))?;
    let value = v.map(format_f64).join(" ");
    Ok(format!("{}{value}{}", &xml[..start], &xml[start + len..]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brisance_core::UniformGridGeometry;

    fn sample() -> CellData {
        CellData {
            geometry: UniformGridGeometry {
                origin: [-0.5, 1.0 / 3.0, 0.0],
                spacing: [0.1, 0.25, 2.0],
                cells: [3, 2, 1],
            },
            fields: vec![
                (
                    "density".to_string(),
                    vec![1.0, 0.1 + 0.2, 1e-300, -4.5, f64::MAX, 6.0],
                ),
                (
                    "pressure".to_string(),
                    vec![101325.0, 2e9, 3.0, 1.0 / 3.0, 0.0, -0.0],
                ),
            ],
        }
    }

    /// The first (only) inline piece of an imported ImageData file, with
    /// its whole extent.
    fn import(path: &Path) -> (Extent, ImageDataPiece) {
        let vtk = Vtk::import(path).unwrap();
        let DataSet::ImageData { extent, pieces, .. } = vtk.data else {
            panic!("not ImageData: {:?}", vtk.data);
        };
        assert_eq!(pieces.len(), 1);
        let Piece::Inline(piece) = pieces.into_iter().next().unwrap() else {
            panic!("piece not inline");
        };
        (extent, *piece)
    }

    /// Each attribute is a one-component Float64 array with the name and
    /// the bits of the matching field.
    fn assert_arrays_are_bit_exact(attributes: &[Attribute], fields: &[(String, Vec<f64>)]) {
        assert_eq!(attributes.len(), fields.len());
        for (attribute, (name, values)) in attributes.iter().zip(fields) {
            let Attribute::DataArray(array) = attribute else {
                panic!("not a data array: {attribute:?}");
            };
            assert_eq!(&array.name, name);
            assert_eq!(array.elem.num_comp(), 1);
            let IOBuffer::F64(read) = &array.data else {
                panic!("not Float64: {:?}", array.data);
            };
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(read), bits(values), "{name}");
        }
    }

    #[test]
    fn fields_and_extent_round_trip_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("snap.vti");
        let data = sample();
        write_vti(&path, &data).unwrap();

        let (whole, piece) = import(&path);
        let expected = Extent::Ranges([0..=3, 0..=2, 0..=1]);
        assert_eq!(whole, expected);
        assert_eq!(piece.extent, expected);
        assert!(piece.data.point.is_empty());
        assert_eq!(piece.data.cell.len(), 2);
        assert_arrays_are_bit_exact(&piece.data.cell, &data.fields);
    }

    #[test]
    fn origin_and_spacing_are_written_with_full_precision() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("snap.vti");
        write_vti(&path, &sample()).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("<VTKFile type=\"ImageData\""), "{text}");
        assert!(text.contains("byte_order=\"LittleEndian\""), "{text}");
        assert!(
            text.contains(
                "<ImageData WholeExtent=\"0 3 0 2 0 1\" \
                 Origin=\"-0.5 0.3333333333333333 0\" Spacing=\"0.1 0.25 2\">"
            ),
            "{text}"
        );
        assert!(text.contains("<DataArray type=\"Float64\" Name=\"pressure\""));
    }

    #[test]
    fn field_of_wrong_length_is_rejected_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("snap.vti");
        let mut data = sample();
        data.fields[1].1.pop();
        let err = write_vti(&path, &data).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        assert!(err.to_string().contains("`pressure` has 5 values"), "{err}");
        assert!(err.to_string().contains(&path.display().to_string()));
        assert!(!path.exists());
    }

    /// A 3 × 2 × 1 node lattice (two active axes) with values that only
    /// read back exactly if every bit is kept.
    fn node_sample() -> NodeData {
        NodeData {
            origin: [-0.25, 1.0 / 3.0, 0.0],
            spacing: [0.5, 0.1, 1.0],
            nodes: [3, 2, 1],
            fields: vec![
                (
                    "mass".to_string(),
                    vec![0.0, 0.25, 1e-300, 0.1 + 0.2, f64::MAX, 7.0],
                ),
                (
                    "velocity_x".to_string(),
                    vec![-1.5, 0.0, -0.0, 1.0 / 3.0, 2e9, f64::MIN_POSITIVE],
                ),
            ],
        }
    }

    #[test]
    fn node_fields_round_trip_exactly_as_point_data() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nodes.vti");
        let data = node_sample();
        write_vti_nodes(&path, &data).unwrap();

        let (whole, piece) = import(&path);
        // Three nodes along x are points 0, 1, 2; one along z is point 0.
        let expected = Extent::Ranges([0..=2, 0..=1, 0..=0]);
        assert_eq!(whole, expected);
        assert_eq!(piece.extent, expected);
        assert!(piece.data.cell.is_empty());
        assert_eq!(piece.data.point.len(), 2);
        assert_arrays_are_bit_exact(&piece.data.point, &data.fields);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains(
                "<ImageData WholeExtent=\"0 2 0 1 0 0\" \
                 Origin=\"-0.25 0.3333333333333333 0\" Spacing=\"0.5 0.1 1\">"
            ),
            "{text}"
        );
        assert!(text.contains("<PointData"), "{text}");
    }

    #[test]
    fn node_field_of_wrong_length_is_rejected_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nodes.vti");
        let mut data = node_sample();
        data.fields[0].1.push(1.0);
        let err = write_vti_nodes(&path, &data).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        assert!(
            err.to_string()
                .contains("`mass` has 7 values but the grid has 6 nodes"),
            "{err}"
        );
        assert!(!path.exists());
        data.nodes = [3, 0, 1];
        let err = write_vti_nodes(&path, &data).unwrap_err();
        assert!(err.to_string().contains("0 nodes in direction 1"), "{err}");
    }

    /// The grid of [`sample`] split into a 2 × 1 × 1 patch layout: cells
    /// i = 0, 1 and i = 2 of both rows.
    fn pieces() -> (UniformGridGeometry, Vec<CellPiece>) {
        let data = sample();
        let take = |lo: usize, n: usize| -> Vec<(String, Vec<f64>)> {
            data.fields
                .iter()
                .map(|(name, v)| {
                    let rows = (0..2).flat_map(|j| v[3 * j + lo..3 * j + lo + n].to_vec());
                    (name.clone(), rows.collect())
                })
                .collect()
        };
        let piece = |patch, lo: usize, n: usize| CellPiece {
            patch,
            lo: [lo, 0, 0],
            cells: [n, 2, 1],
            fields: take(lo, n),
        };
        (data.geometry, vec![piece(0, 0, 2), piece(1, 2, 1)])
    }

    #[test]
    fn a_piece_keeps_its_place_in_the_whole_grid() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p1.vti");
        let (geometry, pieces) = pieces();
        write_vti_piece(&path, &geometry, &pieces[1]).unwrap();
        let (whole, read) = import(&path);
        let expected = Extent::Ranges([2..=3, 0..=2, 0..=1]);
        assert_eq!(whole, expected);
        assert_eq!(read.extent, expected);
        assert_arrays_are_bit_exact(&read.data.cell, &pieces[1].fields);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("Origin=\"-0.5 0.3333333333333333 0\" Spacing=\"0.1 0.25 2\""),
            "{text}"
        );
        let mut short = pieces[1].clone();
        short.fields[0].1.pop();
        let err = write_vti_piece(&dir.path().join("bad.vti"), &geometry, &short).unwrap_err();
        assert!(
            err.to_string()
                .contains("has 1 values but the grid has 2 cells"),
            "{err}"
        );
    }

    #[test]
    fn the_master_lists_every_piece_and_reads_back_as_the_whole_grid() {
        let dir = tempfile::tempdir().unwrap();
        let (geometry, pieces) = pieces();
        std::fs::create_dir(dir.path().join("snap")).unwrap();
        let sources: Vec<String> = (0..2).map(|p| format!("snap/p{p}.vti")).collect();
        for (piece, source) in pieces.iter().zip(&sources) {
            write_vti_piece(&dir.path().join(source), &geometry, piece).unwrap();
        }
        let names: Vec<String> = sample().fields.into_iter().map(|(n, _)| n).collect();
        let extents: Vec<_> = pieces.iter().map(|p| (p.lo, p.cells)).collect();
        let master = dir.path().join("snap.pvti");
        write_pvti(&master, &geometry, &names, &extents, &sources).unwrap();
        assert_eq!(
            std::fs::read_to_string(&master).unwrap(),
            "<?xml version=\"1.0\"?>\n\
             <VTKFile type=\"PImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
             \x20 <PImageData WholeExtent=\"0 3 0 2 0 1\" GhostLevel=\"0\" \
             Origin=\"-0.5 0.3333333333333333 0\" Spacing=\"0.1 0.25 2\">\n\
             \x20   <PCellData>\n\
             \x20     <PDataArray type=\"Float64\" Name=\"density\" NumberOfComponents=\"1\"/>\n\
             \x20     <PDataArray type=\"Float64\" Name=\"pressure\" NumberOfComponents=\"1\"/>\n\
             \x20   </PCellData>\n\
             \x20   <Piece Extent=\"0 2 0 2 0 1\" Source=\"snap/p0.vti\"/>\n\
             \x20   <Piece Extent=\"2 3 0 2 0 1\" Source=\"snap/p1.vti\"/>\n\
             \x20 </PImageData>\n\
             </VTKFile>\n"
        );
        // A VTK reader resolves the pieces from the master.
        let mut vtk = Vtk::import(&master).unwrap();
        vtk.load_all_pieces().unwrap();
        let DataSet::ImageData {
            extent,
            pieces: read,
            ..
        } = vtk.data
        else {
            panic!("not ImageData: {:?}", vtk.data);
        };
        assert_eq!(extent, Extent::Ranges([0..=3, 0..=2, 0..=1]));
        assert_eq!(read.len(), 2);
        for (got, want) in read.into_iter().zip(&pieces) {
            let Piece::Inline(got) = got else {
                panic!("piece not loaded");
            };
            let [a, b, c] = [0, 1, 2].map(|d| {
                let lo = want.lo[d] as i32;
                lo..=lo + want.cells[d] as i32
            });
            assert_eq!(got.extent, Extent::Ranges([a, b, c]));
            assert_arrays_are_bit_exact(&got.data.cell, &want.fields);
        }
    }

    #[test]
    fn a_master_whose_pieces_do_not_tile_the_grid_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("snap.pvti");
        let (geometry, _) = pieces();
        let names = vec!["density".to_string()];
        let two = vec!["a.vti".to_string(), "b.vti".to_string()];
        for extents in [
            // A gap, an overlap, a piece outside the grid, an empty one.
            vec![([0, 0, 0], [2, 2, 1]), ([2, 0, 0], [1, 1, 1])],
            vec![([0, 0, 0], [2, 2, 1]), ([1, 0, 0], [2, 2, 1])],
            vec![([0, 0, 0], [2, 2, 1]), ([2, 0, 0], [2, 2, 1])],
            vec![([0, 0, 0], [3, 2, 1]), ([2, 0, 0], [0, 2, 1])],
        ] {
            let err = write_pvti(&path, &geometry, &names, &extents, &two).unwrap_err();
            assert!(
                err.to_string().contains("do not tile"),
                "{extents:?}: {err}"
            );
        }
        let one = vec![([0, 0, 0], [3, 2, 1])];
        let err = write_pvti(&path, &geometry, &names, &one, &two).unwrap_err();
        assert!(
            err.to_string()
                .contains("1 piece extents but 2 piece files"),
            "{err}"
        );
        assert!(!path.exists());
    }

    #[test]
    fn empty_grid_is_rejected() {
        let mut data = sample();
        data.geometry.cells = [3, 0, 1];
        data.fields.clear();
        let err = write_vti(Path::new("unused.vti"), &data).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
    }
}
