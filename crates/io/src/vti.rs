//! VTK XML ImageData (`.vti`) snapshots of cell-centred fields
//! ([`write_vti`]) and of node fields ([`write_vti_nodes`]).
//!
//! The file is built and serialised with `vtkio`; every field becomes a
//! one-component `Float64` cell-data (or point-data) array stored inline as base64 binary
//! (little-endian, `UInt64` headers), as VTK's own reader (and so
//! ParaView) expects.

use std::path::Path;

use brisance_core::{CellData, NodeData};
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
        counts: data.geometry.cells,
        what: "cells",
        on_points: false,
    };
    let bytes = encode_vti(path, &layout, &data.fields)?;
    write_atomic(path, &bytes)
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
    let mut upper = [0i32; 3];
    for (d, u) in upper.iter_mut().enumerate() {
        let n = layout.counts[d];
        let max = if layout.on_points {
            i32::MAX as usize + 1
        } else {
            i32::MAX as usize
        };
        if n == 0 || n > max {
            return Err(IoError::invalid_input(
                path,
                format!("grid has {n} {what} in direction {d}; VTK needs 1 to {max}"),
            ));
        }
        // Points run 0 ..= n − 1; cells 0 .. n, whose points run 0 ..= n.
        *u = (if layout.on_points { n - 1 } else { n }) as i32;
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
    let extent = Extent::Ranges([0..=upper[0], 0..=upper[1], 0..=upper[2]]);
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

    #[test]
    fn empty_grid_is_rejected() {
        let mut data = sample();
        data.geometry.cells = [3, 0, 1];
        data.fields.clear();
        let err = write_vti(Path::new("unused.vti"), &data).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
    }
}
