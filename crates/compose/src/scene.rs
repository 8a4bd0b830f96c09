//! The scenario's shared parts as a pipeline crate reads them
//! ([`brisance_scene::Scene`]): what the composer hands a pipeline that
//! owns its config section, validation and builder
//! ([`brisance_scene::PipelineSpec`]).

use brisance_scene::{Domain, InitialRegion, Material, Scene};

use crate::config::Scenario;

/// The scene of `s`: its domain, end time, materials (with their EOS once
/// the scenario is loaded), initial regions and requested cell fields.
pub fn scene_of(s: &Scenario) -> Scene<'_> {
    Scene {
        name: &s.name,
        domain: Domain {
            lower: s.domain.lower,
            upper: s.domain.upper,
            cells: s.domain.cells,
            patches: s.domain.patches,
            geometry: s.domain.geometry,
        },
        end_time: s.time.end,
        materials: s
            .materials
            .iter()
            .map(|(name, m)| Material { name, eos: m.eos() })
            .collect(),
        initial: s
            .initial
            .iter()
            .map(|r| InitialRegion {
                region: &r.region,
                material: &r.material,
                velocity: r.state.velocity,
            })
            .collect(),
        cell_fields: &s.outputs.fields,
        line_outs: s.outputs.lineouts.len(),
    }
}
