//! The registry of named components: what `brisance list` prints and what a
//! config may name. Each entry carries a RON example that the tests parse,
//! so the list cannot drift from the schema.

/// One named component.
#[derive(Debug, Clone, Copy)]
pub struct Entry {
    /// Family: `eos`, `material`, `reaction`, `pipeline`, `region`, `boundary`.
    pub family: &'static str,
    /// The name a config uses.
    pub name: &'static str,
    /// One line on what it is, with its seed reference.
    pub summary: &'static str,
    /// A RON example of the config value.
    pub example: &'static str,
}

/// Every registered component.
pub const ENTRIES: &[Entry] = &[
    Entry {
        family: "eos",
        name: "IdealGas",
        summary: "gamma-law gas p = (gamma-1) rho e with constant cv (seed 001 eq 55)",
        example: "IdealGas(gamma: 1.4, cv: 717.6, reference_density: 1.225)",
    },
    Entry {
        family: "pipeline",
        name: "Fdm",
        summary: "3D Lax-Wendroff finite-difference Euler solver, Yanenko splitting, adaptive viscosity (seed 001 §2.1)",
        example: "Fdm(material: \"air\", viscosity: Adaptive)",
    },
    Entry { family: "region", name: "Everywhere", summary: "the whole domain", example: "Everywhere" },
    Entry { family: "region", name: "Box", summary: "axis-aligned box", example: "Box(min: (0, 0, 0), max: (1, 1, 1))" },
    Entry { family: "region", name: "Sphere", summary: "ball", example: "Sphere(centre: (0, 0, 0), radius: 0.1)" },
    Entry {
        family: "region",
        name: "Cylinder",
        summary: "finite circular cylinder from a base point along an axis",
        example: "Cylinder(base: (0, 0, 0), axis: (0, 0, 1), radius: 0.1, length: 0.5)",
    },
    Entry {
        family: "region",
        name: "HalfSpace",
        summary: "points on the side of a plane the normal points to",
        example: "HalfSpace(point: (0.5, 0, 0), normal: (1, 0, 0))",
    },
    Entry { family: "boundary", name: "Outflow", summary: "zero-gradient outflow", example: "Outflow" },
    Entry { family: "boundary", name: "Reflective", summary: "slip wall / symmetry plane", example: "Reflective" },
    Entry { family: "boundary", name: "Periodic", summary: "periodic (both faces of an axis)", example: "Periodic" },
    Entry {
        family: "boundary",
        name: "Fixed",
        summary: "fixed state of the pipeline's gas",
        example: "Fixed(density: 1.225, pressure: 101325)",
    },
];

/// Families in display order, with what is still to come.
pub const FAMILIES: &[(&str, &str)] = &[
    ("eos", "equations of state"),
    ("material", "constitutive models"),
    ("reaction", "reaction models"),
    ("pipeline", "pipelines"),
    ("region", "initial-region shapes"),
    ("boundary", "boundary conditions"),
];

/// The listing `brisance list` prints.
pub fn listing() -> String {
    let mut out = String::new();
    for (family, title) in FAMILIES {
        out.push_str(&format!("{title} ({family}):\n"));
        let entries: Vec<&Entry> = ENTRIES.iter().filter(|e| e.family == *family).collect();
        if entries.is_empty() {
            out.push_str("  (none registered yet)\n");
        }
        for e in entries {
            out.push_str(&format!("  {:<12} {}\n", e.name, e.summary));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{BoundaryConfig, EosConfig, Pipeline, Region};
    use crate::load::ron_options;

    #[test]
    fn every_example_parses_as_its_family_and_names_its_variant() {
        for e in ENTRIES {
            let ok = match e.family {
                "eos" => ron_options().from_str::<EosConfig>(e.example).map(|_| ()),
                "pipeline" => ron_options().from_str::<Pipeline>(e.example).map(|_| ()),
                "region" => ron_options().from_str::<Region>(e.example).map(|_| ()),
                "boundary" => ron_options()
                    .from_str::<BoundaryConfig>(e.example)
                    .map(|_| ()),
                other => panic!("no parser for family {other}"),
            };
            assert!(ok.is_ok(), "{} example `{}`: {:?}", e.name, e.example, ok);
            assert!(
                e.example.starts_with(e.name),
                "{} example must use its name",
                e.name
            );
        }
    }

    #[test]
    fn listing_names_every_entry() {
        let l = listing();
        for e in ENTRIES {
            assert!(l.contains(e.name));
        }
        assert!(l.contains("constitutive models (material):\n  (none registered yet)"));
    }
}
