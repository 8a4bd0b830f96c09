//! VTK XML ImageData (`.vti`) snapshots of cell-centred fields.
//!
//! The file is built and serialised with `vtkio`; every field becomes a
//! one-component `Float64` cell-data array stored inline as base64 binary
//! (little-endian, `UInt64` headers), as VTK's own reader (and so
//! ParaView) expects.

use std::path::Path;

use brisance_core::CellData;
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
    let bytes = encode_vti(path, data)?;
    write_atomic(path, &bytes)
}

/// The bytes of the `.vti` file for `data`; `path` only names the target in
/// errors.
fn encode_vti(path: &Path, data: &CellData) -> Result<Vec<u8>, IoError> {
    let geometry = &data.geometry;
    let cells = geometry.cell_count();
    let mut upper = [0i32; 3];
    for (d, u) in upper.iter_mut().enumerate() {
        *u = i32::try_from(geometry.cells[d])
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| {
                IoError::invalid_input(
                    path,
                    format!(
                        "grid has {} cells in direction {d}; VTK needs 1 to {}",
                        geometry.cells[d],
                        i32::MAX
                    ),
                )
            })?;
    }
    let mut arrays = Vec::with_capacity(data.fields.len());
    for (name, values) in &data.fields {
        if values.len() != cells {
            return Err(IoError::invalid_input(
                path,
                format!(
                    "field `{name}` has {} values but the grid has {cells} cells",
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
    let extent = Extent::Ranges([0..=upper[0], 0..=upper[1], 0..=upper[2]]);
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::ImageData {
            extent: extent.clone(),
            // vtkio stores these as f32; the exact f64 text is patched in
            // below.
            origin: geometry.origin.map(|x| x as f32),
            spacing: geometry.spacing.map(|x| x as f32),
            meta: None,
            pieces: vec![Piece::Inline(Box::new(ImageDataPiece {
                extent,
                data: Attributes {
                    point: Vec::new(),
                    cell: arrays,
                },
            }))],
        },
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes)
        .map_err(|e| IoError::encode(path, e.to_string()))?;
    let text = String::from_utf8(bytes).map_err(|e| IoError::encode(path, e.to_string()))?;
    let text = replace_attribute(path, &text, "Origin", geometry.origin)?;
    let text = replace_attribute(path, &text, "Spacing", geometry.spacing)?;
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
        for (attribute, (name, values)) in piece.data.cell.iter().zip(&data.fields) {
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

    #[test]
    fn empty_grid_is_rejected() {
        let mut data = sample();
        data.geometry.cells = [3, 0, 1];
        data.fields.clear();
        let err = write_vti(Path::new("unused.vti"), &data).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
    }
}
