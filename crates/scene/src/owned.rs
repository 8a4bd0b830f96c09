//! A scenario's shared parts held by value, from which a [`Scene`] is
//! borrowed: for a pipeline crate's tests and for tools that drive a
//! pipeline without a RON file.

use brisance_constitutive::MaterialModel;
use brisance_core::Geometry;
use brisance_eos::EosModel;
use brisance_grid::Shape;

use crate::{
    Boundaries, Domain, InitialRegion, Material, OutputsSummary, ParticleGauge, Scene, StateConfig,
    ThermalConfig, OPEN_FACES,
};

/// The owned counterpart of [`Scene`]; [`OwnedScene::scene`] lends it.
#[derive(Debug, Clone, PartialEq)]
pub struct OwnedScene {
    /// The scenario's name.
    pub name: String,
    /// The domain.
    pub domain: Domain,
    /// End time, s.
    pub end_time: f64,
    /// The Courant number of the time step.
    pub cfl: f64,
    /// The six faces' boundary conditions.
    pub boundaries: Boundaries,
    /// The materials by name with their equations of state, in order.
    pub materials: Vec<(String, Option<EosModel>)>,
    /// The constitutive models (and thermal properties) of the materials
    /// that have one, by name.
    pub models: Vec<(String, MaterialModel, Option<ThermalConfig>)>,
    /// The initial regions (shape, material, state), in order.
    pub initial: Vec<(Shape, String, StateConfig)>,
    /// The cell fields the outputs ask for.
    pub cell_fields: Vec<String>,
    /// How many line-outs the outputs ask for.
    pub line_outs: usize,
    /// The particle gauges (name, region, material), in order.
    pub particle_gauges: Vec<(String, Shape, Option<String>)>,
    /// Every list of cell fields the outputs name, with its path.
    pub field_lists: Vec<(String, Vec<String>)>,
    /// What else the outputs ask for.
    pub outputs: OutputsSummary,
}

impl Domain {
    /// A Cartesian box of `cells` from `lower` to `upper` in one patch.
    pub fn cartesian(lower: [f64; 3], upper: [f64; 3], cells: [usize; 3]) -> Self {
        Self {
            lower,
            upper,
            cells,
            patches: [1; 3],
            geometry: Geometry::Cartesian,
        }
    }
}

impl StateConfig {
    /// A state at rest of `density` (kg/m³) and `pressure` (Pa).
    pub fn at_pressure(density: f64, pressure: f64) -> Self {
        Self {
            density,
            velocity: [0.0; 3],
            pressure: Some(pressure),
            specific_internal_energy: None,
            temperature: None,
            material: None,
        }
    }

    /// The same state moving at `velocity`, m/s.
    pub fn moving(mut self, velocity: [f64; 3]) -> Self {
        self.velocity = velocity;
        self
    }
}

impl OwnedScene {
    /// A scene called `scene` on `domain` with no materials or regions:
    /// end time 1 µs, Courant number 0.5, six open faces, no outputs.
    pub fn new(domain: Domain) -> Self {
        Self {
            name: "scene".into(),
            domain,
            end_time: 1e-6,
            cfl: 0.5,
            boundaries: OPEN_FACES.clone(),
            materials: Vec::new(),
            models: Vec::new(),
            initial: Vec::new(),
            cell_fields: Vec::new(),
            line_outs: 0,
            particle_gauges: Vec::new(),
            field_lists: Vec::new(),
            outputs: OutputsSummary::default(),
        }
    }

    /// Adds the material `name` with equation of state `eos`.
    pub fn with_material(mut self, name: &str, eos: Option<EosModel>) -> Self {
        self.materials.push((name.into(), eos));
        self
    }

    /// Gives the material `name` (added with [`Self::with_material`]) the
    /// constitutive `model` and `thermal` properties of a particle solid.
    pub fn with_model(
        mut self,
        name: &str,
        model: MaterialModel,
        thermal: Option<ThermalConfig>,
    ) -> Self {
        self.models.push((name.into(), model, thermal));
        self
    }

    /// Adds an initial region of `material` in `state` (after the others,
    /// so it overrides them where they overlap).
    pub fn with_region(mut self, region: Shape, material: &str, state: StateConfig) -> Self {
        self.initial.push((region, material.into(), state));
        self
    }

    /// The scene, borrowed.
    pub fn scene(&self) -> Scene<'_> {
        Scene {
            name: &self.name,
            domain: self.domain,
            end_time: self.end_time,
            cfl: self.cfl,
            boundaries: &self.boundaries,
            materials: self
                .materials
                .iter()
                .map(|(name, eos)| {
                    let solid = self.models.iter().find(|(n, ..)| n == name);
                    Material {
                        name,
                        eos: eos.as_ref(),
                        model: solid.map(|(_, m, _)| m),
                        thermal: solid.and_then(|(.., t)| t.as_ref()),
                    }
                })
                .collect(),
            initial: self
                .initial
                .iter()
                .map(|(region, material, state)| InitialRegion {
                    region,
                    material,
                    state,
                })
                .collect(),
            cell_fields: &self.cell_fields,
            line_outs: self.line_outs,
            particle_gauges: self
                .particle_gauges
                .iter()
                .map(|(name, region, material)| ParticleGauge {
                    name,
                    region,
                    material: material.as_deref(),
                })
                .collect(),
            field_lists: self
                .field_lists
                .iter()
                .map(|(path, fields)| (path.clone(), fields.as_slice()))
                .collect(),
            outputs: self.outputs,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lent scene holds the owned parts, in order.
    #[test]
    fn the_scene_lends_every_part() {
        let mut o = OwnedScene::new(Domain::cartesian([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1]))
            .with_material(
                "air",
                Some(EosModel::IdealGas(brisance_eos::IdealGas::air())),
            )
            .with_region(
                Shape::Everywhere,
                "air",
                StateConfig::at_pressure(1.2, 1e5).moving([1.0, 2.0, 3.0]),
            );
        let steel = MaterialModel::ElasticPlastic(
            brisance_constitutive::ElasticPlastic::steel_4340_seed000(),
        );
        let thermal = ThermalConfig {
            conductivity: 44.5,
            specific_heat: Some(477.0),
        };
        o = o
            .with_material("steel", None)
            .with_model("steel", steel.clone(), Some(thermal));
        o.field_lists = vec![("outputs.fields".into(), vec!["pressure".into()])];
        o.outputs.gauges = 3;
        o.particle_gauges = vec![("plate".into(), Shape::Everywhere, Some("steel".into()))];
        let s = o.scene();
        assert_eq!(s.name, "scene");
        assert_eq!(s.domain.cells, [2, 1, 1]);
        assert!(s.material("air").and_then(|m| m.eos).is_some());
        let air = s.material("air").unwrap();
        assert!(air.model.is_none() && air.thermal.is_none());
        let solid = s.material("steel").unwrap();
        assert_eq!(solid.model, Some(&steel));
        assert_eq!(solid.thermal, Some(&thermal));
        assert_eq!(
            s.particle_gauges,
            [ParticleGauge {
                name: "plate",
                region: &Shape::Everywhere,
                material: Some("steel"),
            }]
        );
        assert_eq!(s.initial[0].material, "air");
        assert_eq!(s.initial[0].state.velocity, [1.0, 2.0, 3.0]);
        assert_eq!(s.initial[0].state.pressure, Some(1e5));
        assert_eq!(s.field_lists[0].1, ["pressure".to_string()]);
        assert_eq!(s.outputs.gauges, 3);
        assert_eq!(s.boundaries, &OPEN_FACES);
    }
}
