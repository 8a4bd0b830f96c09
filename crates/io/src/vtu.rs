//! VTK XML UnstructuredGrid (`.vtu`) snapshots of particle sets: every
//! particle is a `VTK_VERTEX` cell with its fields as `Float64` point data,
//! which ParaView shows directly (Point Gaussian or Points representation).

use std::path::Path;

use brisance_core::ParticleData;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, Piece,
    UnstructuredGridPiece, Version, VertexNumbers,
};
use vtkio::{IOBuffer, Vtk};

use crate::atomic::write_atomic;
use crate::IoError;

/// Writes `data` as a VTK XML UnstructuredGrid of vertices at `path`
/// (atomically). Fails without writing if a field does not have exactly
/// one value per point.
pub fn write_vtu(path: &Path, data: &ParticleData) -> Result<(), IoError> {
    let n = data.positions.len();
    let mut arrays = Vec::with_capacity(data.fields.len());
    for (name, values) in &data.fields {
        if values.len() != n {
            return Err(IoError::invalid_input(
                path,
                format!(
                    "field `{name}` has {} values for {n} particles",
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
    let points: Vec<f64> = data.positions.iter().flatten().copied().collect();
    let cells = Cells {
        cell_verts: VertexNumbers::XML {
            connectivity: (0..n as u64).collect(),
            offsets: (1..=n as u64).collect(),
        },
        types: vec![CellType::Vertex; n],
    };
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::UnstructuredGrid {
            meta: None,
            pieces: vec![Piece::Inline(Box::new(UnstructuredGridPiece {
                points: IOBuffer::F64(points),
                cells,
                data: Attributes {
                    point: arrays,
                    cell: Vec::new(),
                },
            }))],
        },
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes)
        .map_err(|e| IoError::encode(path, e.to_string()))?;
    write_atomic(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ParticleData {
        ParticleData {
            positions: vec![[0.0, 1.0, 2.0], [0.5, -1.0, 1e-3]],
            fields: vec![
                ("mass".to_string(), vec![1.5, 0.1 + 0.2]),
                ("pressure".to_string(), vec![-2.0, 1e9]),
            ],
        }
    }

    #[test]
    fn particles_round_trip_through_vtkio() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.vtu");
        write_vtu(&path, &sample()).unwrap();
        let vtk = Vtk::import(&path).unwrap();
        let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid");
        };
        let Piece::Inline(piece) = &pieces[0] else {
            panic!("not inline");
        };
        assert_eq!(
            piece.points.clone().into_vec::<f64>().unwrap(),
            vec![0.0, 1.0, 2.0, 0.5, -1.0, 1e-3]
        );
        assert_eq!(piece.cells.types, vec![CellType::Vertex; 2]);
        let Attribute::DataArray(mass) = &piece.data.point[0] else {
            panic!("no point data");
        };
        assert_eq!(mass.name, "mass");
        assert_eq!(
            mass.data.clone().into_vec::<f64>().unwrap(),
            vec![1.5, 0.1 + 0.2]
        );
    }

    #[test]
    fn a_short_field_is_rejected_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.vtu");
        let mut data = sample();
        data.fields[0].1.pop();
        assert!(write_vtu(&path, &data)
            .unwrap_err()
            .to_string()
            .contains("mass"));
        assert!(!path.exists());
    }
}
