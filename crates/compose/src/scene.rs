//! The scenario's shared parts as a pipeline crate reads them
//! ([`brisance_scene::Scene`]): what the composer hands a pipeline that
//! owns its config section, validation and builder
//! ([`brisance_scene::PipelineSpec`]).

use brisance_scene::{Domain, InitialRegion, Material, OutputsSummary, ParticleGauge, Scene};

use crate::config::Scenario;

/// The scene of `s`: its domain, end time, Courant number, faces, materials
/// (with their EOS once the scenario is loaded, their constitutive models
/// and thermal properties), initial regions and requested outputs.
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
        cfl: s.time.cfl,
        boundaries: &s.boundaries,
        materials: s
            .materials
            .iter()
            .map(|(name, m)| Material {
                name,
                eos: m.eos(),
                model: m.model.as_ref(),
                thermal: m.thermal.as_ref(),
            })
            .collect(),
        initial: s
            .initial
            .iter()
            .map(|r| InitialRegion {
                region: &r.region,
                material: &r.material,
                state: &r.state,
            })
            .collect(),
        cell_fields: &s.outputs.fields,
        line_outs: s.outputs.lineouts.len(),
        particle_gauges: s
            .outputs
            .particle_gauges
            .iter()
            .map(|g| ParticleGauge {
                name: &g.name,
                region: &g.region,
                material: g.material.as_deref(),
            })
            .collect(),
        field_lists: std::iter::once(("outputs.fields".to_string(), s.outputs.fields.as_slice()))
            .chain(
                s.outputs
                    .gauges
                    .iter()
                    .enumerate()
                    .map(|(k, g)| (format!("outputs.gauges.{k}.fields"), g.fields.as_slice())),
            )
            .chain(
                s.outputs
                    .lineouts
                    .iter()
                    .enumerate()
                    .map(|(k, l)| (format!("outputs.lineouts.{k}.fields"), l.fields.as_slice())),
            )
            .collect(),
        outputs: OutputsSummary {
            interval: s.outputs.interval,
            gauges: s.outputs.gauges.len(),
            checkpoint_every: s.outputs.checkpoint_every,
        },
    }
}
