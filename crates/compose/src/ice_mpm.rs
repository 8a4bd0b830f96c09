//! The `IceMpm` pipeline through the composer: its shipped scenarios,
//! `--set` paths and error positions. The section, its checks and its
//! builder are `brisance_couple::ice_mpm::pipeline`'s.

/// The coupled solver of an `IceMpm` scenario, by its section's type.
#[cfg(test)]
fn icempm(s: &crate::config::Scenario) -> brisance_couple::IceMpm {
    let section = s.pipeline.section::<brisance_couple::IceMpmConfig>();
    crate::build::build_section(section.expect("an IceMpm pipeline"), s).unwrap()
}

mod tests {
    use crate::build::build_solver;
    use crate::load_str;

    const PISTON: &str = include_str!("../../../configs/piston_icempm.ron");

    /// configs/piston_icempm.ron builds through the pipeline and, at
    /// 100 µs, its shock (p crossing 1.25 bar) is within two cells of the
    /// exact 412.3 m/s piston shock launched from x = 6 cm, and the
    /// piston gauge still reads 100 m/s within 0.5 %.
    #[test]
    fn the_piston_config_drives_the_exact_shock() {
        let loaded = load_str("piston_icempm.ron", PISTON, &[]).unwrap();
        let mut built = build_solver(&loaded.scenario).unwrap();
        while built.time() < 1e-4 * (1.0 - 1e-12) {
            let dt = built.stable_dt().unwrap().min(1e-4 - built.time());
            built.advance(dt).unwrap();
        }
        let mut v = Vec::new();
        assert!(built.sample_particle_gauge(0, &[brisance_mpm::SetQuantity::MeanVelocity], &mut v));
        assert!((v[0] / 100.0 - 1.0).abs() < 5e-3, "piston at {} m/s", v[0]);
        let p = built.cell_data(&["pressure".into()]).unwrap();
        let p = p.field("pressure").unwrap();
        let level = 1.25e5;
        let i = (1..p.len())
            .rev()
            .find(|&i| p[i - 1] >= level && p[i] < level)
            .unwrap();
        let x = 1e-3 * (i as f64 - 0.5) + 1e-3 * (p[i - 1] - level) / (p[i - 1] - p[i]);
        let exact = 0.06 + 412.3 * 1e-4;
        assert!(
            ((x - exact) / 1e-3).abs() < 2.0,
            "shock at {x} m, exact {exact} m"
        );
    }

    /// A solid's region is named by its index in the scenario's
    /// `initial`, the fluids' regions before it counted: the piston's steel
    /// (a `Linear` pressure, no equation of state in its model) given a
    /// pressure instead of its temperature is refused at `initial.1.state`.
    #[test]
    fn a_solid_region_is_named_by_its_index_among_all_regions() {
        let bad = PISTON.replace(
            "velocity: (100.0, 0.0, 0.0), temperature: 300.0)",
            "velocity: (100.0, 0.0, 0.0), pressure: 101325.0)",
        );
        let loaded = load_str("piston_icempm.ron", &bad, &[]).unwrap();
        let err = build_solver(&loaded.scenario).err().expect("refused");
        assert_eq!(err.field.as_deref(), Some("initial.1.state"), "{err}");
        assert!(err.to_string().contains("temperature"), "{err}");
    }

    /// The particles' section is checked as the `Mpm` pipeline's is, at
    /// its paths under `pipeline.mpm` (`--set` reaches it there too).
    #[test]
    fn the_particle_section_is_checked_under_pipeline_mpm() {
        for (set, field) in [
            ("pipeline.mpm.ppc=0", "pipeline.mpm.ppc"),
            ("pipeline.mpm.ppc=9", "pipeline.mpm.ppc"),
            ("pipeline.mpm.mass_cutoff=1.5", "pipeline.mpm.mass_cutoff"),
            (
                "pipeline.mpm.bulk_viscosity=On(quadratic: -1.0, linear: 0.06)",
                "pipeline.mpm.bulk_viscosity.quadratic",
            ),
        ] {
            let err = load_str("piston_icempm.ron", PISTON, &[set.to_string()])
                .err()
                .unwrap_or_else(|| panic!("`{set}` refused"));
            assert!(
                err.to_string().contains(field),
                "`{set}`: {err} does not name {field}"
            );
        }
    }

    #[test]
    fn a_solid_listed_among_the_fluids_is_named() {
        let bad = PISTON.replace(
            "ice: (materials: [\"air\"])",
            "ice: (materials: [\"air\", \"steel\"])",
        );
        let err = load_str("piston_icempm.ron", &bad, &[]).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("pipeline.solid"), "{text}");
    }
}

mod slip_tests {
    use crate::build::build_solver;
    use crate::load_str;

    /// Air streaming at 50 m/s along a steel slab at rest (periodic along
    /// the stream, the slab's faces across it; 1 mm cells, the steel's
    /// projection smeared over the cells beside its faces).
    const SHEAR: &str = r#"Scenario(
    name: "shear",
    domain: (lower: (0.0, 0.0, 0.0), upper: (0.004, 0.02, 0.001), cells: (4, 20, 1)),
    boundaries: (x_low: Periodic, x_high: Periodic, y_low: Reflective, y_high: Reflective),
    time: (end: 1.0e-5, cfl: 0.4),
    materials: {
        "air": (eos: IdealGas(gamma: 1.4, cv: 717.5, rho0: 1.225)),
        "steel": (
            eos: SolidThreshold(solid: Murnaghan(n: 4.0, kappa: 6.25e-12, rho0: 7850.0, cv: 460.0, t_ref: 300.0), threshold_pressure: 101325.0),
            model: Hypoelastic(shear_modulus: 80.0e9, pressure: Linear(bulk_modulus: 160.0e9), rate: Jaumann),
        ),
    },
    pipeline: IceMpm(
        ice: (materials: ["air"]EXCHANGE),
        solid: "steel",
        mpm: (shape_function: Linear, scheme: Musl, ppc: 2, mass_cutoff: 1e-3),
    ),
    initial: [
        (region: Everywhere, material: "air", state: (density: 1.17659, pressure: 101325.0, velocity: (50.0, 0.0, 0.0))),
        (region: Box(min: (-1.0, 0.008, -1.0), max: (1.0, 0.012, 1.0)), material: "steel", state: (density: 7850.00497, temperature: 300.0)),
    ],
)"#;

    /// After 20 steps: per row of cells, the steel's volume fraction and
    /// the air's and the steel's velocity along the stream, and the
    /// x-momentum per unit depth of the fluids' and particles' sum at the
    /// start and end.
    fn run(exchange: &str) -> Vec<(f64, f64, f64)> {
        run_on(exchange, &[])
    }

    fn run_on(exchange: &str, set: &[String]) -> Vec<(f64, f64, f64)> {
        let text = SHEAR.replace("EXCHANGE", exchange);
        let loaded = load_str("shear.ron", &text, set).unwrap();
        let mut built = build_solver(&loaded.scenario).unwrap();
        for _ in 0..20 {
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
        }
        let names: Vec<String> = ["volume_fraction_2", "velocity_x_1", "velocity_x_2"]
            .map(String::from)
            .to_vec();
        let data = built.cell_data(&names).unwrap();
        let f = |n: &str| data.field(n).unwrap().to_vec();
        let (theta, air, steel) = (f(&names[0]), f(&names[1]), f(&names[2]));
        (0..20)
            .map(|j| (theta[4 * j], air[4 * j], steel[4 * j]))
            .collect()
    }

    /// The rows of cells beside the slab's faces (centres at y = 7.5 and
    /// 12.5 mm, outside the slab, where the air starts at 50 m/s) hold a
    /// quarter of steel from its smeared projection. With `Slip` the air
    /// there keeps its 50 m/s along the slab (the surface's normal is
    /// across the stream, so nothing along it couples the two) and the
    /// steel stays at rest to 10⁻⁶ m/s; with the isotropic exchange of
    /// eq 29 the same cells' air is held to the steel, and the steel set
    /// moving, by 8·10⁻⁴ m/s after 20 steps. (Inside the slab the air
    /// starts at the slab's state, at rest.)
    #[test]
    fn air_slips_along_a_slab_under_the_slip_exchange() {
        let slip = run(", solid_exchange: Slip");
        let iso = run("");
        for j in [7, 12] {
            let (theta, air, steel) = slip[j];
            assert!(theta > 0.2 && theta < 0.3, "row {j}: θ = {theta}");
            assert!((air - 50.0).abs() < 1e-9, "row {j}: air at {air} m/s");
            assert!(steel.abs() < 1e-6, "row {j}: steel at {steel} m/s");
            let (_, air_iso, steel_iso) = iso[j];
            assert!(air_iso < 1e-2, "row {j}: isotropic air at {air_iso} m/s");
            assert!(
                steel_iso > 1e-4,
                "row {j}: isotropic steel at {steel_iso} m/s"
            );
        }
    }

    /// The slip exchange reads the solid's volume fraction in the
    /// neighbouring cells (the ghosts across a patch's edge included): the
    /// bits are the same on one patch and on four.
    #[test]
    fn slip_gives_the_same_bits_on_any_patch_split() {
        let one = run_on(", solid_exchange: Slip", &[]);
        let four = run_on(
            ", solid_exchange: Slip",
            &["domain.patches=(2,2,1)".to_string()],
        );
        for (a, b) in one.iter().zip(&four) {
            assert_eq!(a.1.to_bits(), b.1.to_bits(), "{one:?} vs {four:?}");
            assert_eq!(a.2.to_bits(), b.2.to_bits(), "{one:?} vs {four:?}");
        }
    }

    /// The Ice pipeline alone has no solid to slip along: the field is
    /// refused by name.
    #[test]
    fn slip_needs_particles() {
        let text = include_str!("../../../configs/sod_ice.ron").replace(
            "pipeline: Ice(materials: [\"gas\"]),",
            "pipeline: Ice(materials: [\"gas\"], solid_exchange: Slip),",
        );
        let err = load_str("sod_ice.ron", &text, &[]).unwrap_err();
        assert_eq!(
            err.field.as_deref(),
            Some("pipeline.solid_exchange"),
            "{err}"
        );
        let ok = SHEAR.replace("EXCHANGE", ", solid_exchange: Slip");
        let loaded = load_str("shear.ron", &ok, &[]).unwrap();
        let Some(c) = loaded
            .scenario
            .pipeline
            .section::<brisance_couple::IceMpmConfig>()
        else {
            panic!("an IceMpm pipeline");
        };
        assert_eq!(c.ice.solid_exchange, brisance_ice::SolidExchange::Slip);
    }
}

mod cylinder_tests {
    use crate::build::build_solver;
    use crate::load_str;

    const CYLINDER_RZ: &str = include_str!("../../../configs/cylinder_rz.ron");
    const CYLINDER: &str = include_str!("../../../configs/cylinder_icempm.ron");

    /// configs/cylinder_icempm.ron builds (four materials, the copper tube
    /// as particles) and takes its first steps with a positive, finite
    /// pressure everywhere and the booster's pressure at the tube's end.
    #[test]
    fn the_cylinder_config_builds_and_steps() {
        let loaded = load_str("cylinder_icempm.ron", CYLINDER, &[]).unwrap();
        let mut built = build_solver(&loaded.scenario).unwrap();
        for _ in 0..3 {
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
        }
        let p = built.cell_data(&["pressure".into()]).unwrap();
        let p = p.field("pressure").unwrap();
        assert!(p.iter().all(|x| *x > 0.0 && x.is_finite()));
        // The booster's 10 GPa is there at the start of the tube.
        assert!(p[0] > 1e9, "p at the booster {} Pa", p[0]);
    }

    /// configs/cylinder_rz.ron at its 2 mm cells: in the first steps the
    /// coupled equilibration (step 2) takes QM-100 out of the cells the
    /// copper's projected volume settles into, 9.0 % of E(0) with its heat
    /// of reaction by the fifth step. The reactant's mass carries its heat
    /// of reaction in the totals, so the rescale books it too: the coupled
    /// total (fluids + particles − rescale) is the start's to 1e-4 of E(0)
    /// (measured −3.5e-5: the coupling's own error), where booking the
    /// rescale without the heat of reaction left −7.0 %.
    #[test]
    fn the_rescale_of_a_reactant_books_its_heat_of_reaction() {
        use brisance_core::Solver;
        let loaded = load_str("cylinder_rz.ron", CYLINDER_RZ, &[]).unwrap();
        let mut solver = super::icempm(&loaded.scenario);
        let (e0, r0) = (
            solver.conservation_totals().energy,
            solver.rescaled_totals().energy,
        );
        for _ in 0..5 {
            let dt = solver.stable_dt().unwrap();
            solver.advance(dt).unwrap();
        }
        let took = (solver.rescaled_totals().energy - r0) / e0;
        let drift = solver.conservation_totals().energy / e0 - 1.0;
        assert!(took < -0.05, "the rescale took {took:e} of E(0)");
        assert!(drift.abs() < 1e-4, "drift {drift:e} of E(0)");
    }
}

mod solids_tests {
    use super::icempm;
    use crate::load_str;
    use brisance_core::Solver;

    const PISTON: &str = include_str!("../../../configs/piston_icempm.ron");

    /// The piston config with the piston split into two materials of the
    /// same steel (`solid: ["steel", "steel_b"]`).
    fn two_steels() -> String {
        PISTON
            .replace(
                "solid: \"steel\",",
                "solid: [\"steel_b\", \"steel\"],",
            )
            .replace(
                "    },\n    pipeline:",
                "        \"steel_b\": (\n            eos: SolidThreshold(solid: Murnaghan(n: 4.0, kappa: 6.25e-12, rho0: 7850.0, cv: 460.0, t_ref: 300.0), threshold_pressure: 101325.0),\n            model: Hypoelastic(shear_modulus: 80.0e9, pressure: Linear(bulk_modulus: 160.0e9), rate: Jaumann),\n        ),\n    },\n    pipeline:",
            )
            .replace(
                "(region: Box(min: (0.05, -1.0, -1.0), max: (0.06, 1.0, 1.0)), material: \"steel\",",
                "(region: Box(min: (0.05, -1.0, -1.0), max: (0.055, 1.0, 1.0)), material: \"steel\", state: (density: 7850.00497, velocity: (100.0, 0.0, 0.0), temperature: 300.0)),\n        (region: Box(min: (0.055, -1.0, -1.0), max: (0.06, 1.0, 1.0)), material: \"steel_b\",",
            )
    }

    /// Two solids from a list build as materials 2 and 3 of the output
    /// fields in the order given (`volume_fraction_2` is steel_b's, listed
    /// first, the front half of the piston),
    /// and the piston of two materials moves at 100 m/s after 50 steps.
    #[test]
    fn a_list_of_solids_builds_in_the_order_given_and_runs() {
        let text = two_steels();
        let loaded = load_str("two_steels.ron", &text, &[]).unwrap();
        let mut built = icempm(&loaded.scenario);
        assert_eq!(built.solids(), vec![2, 1]);
        for _ in 0..50 {
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
        }
        let f = built
            .cell_data(&["volume_fraction_2".into(), "volume_fraction_3".into()])
            .unwrap();
        let (a, b) = (
            f.field("volume_fraction_2").unwrap(),
            f.field("volume_fraction_3").unwrap(),
        );
        // Cell 57 (57–58 mm; the piston has moved 0.4 mm) is steel_b
        // (material 2), cell 51 steel (material 3).
        assert!(a[57] > 0.9 && b[51] > 0.9, "{} {}", a[57], b[51]);
        assert!(a[51] < 1e-5 && b[57] < 1e-5, "{} {}", a[51], b[57]);
        let mut v = Vec::new();
        assert!(built.sample_particle_gauge(0, &[brisance_mpm::SetQuantity::MeanVelocity], &mut v));
        assert!((v[0] / 100.0 - 1.0).abs() < 5e-3, "piston at {} m/s", v[0]);
    }

    /// A solid named twice, or a solid as a reaction's product, is refused
    /// at its field.
    #[test]
    fn bad_solid_lists_name_the_field() {
        let twice = two_steels().replace(
            "solid: [\"steel_b\", \"steel\"],",
            "solid: [\"steel\", \"steel\"],",
        );
        let e = load_str("twice.ron", &twice, &[]).unwrap_err().to_string();
        assert!(e.contains("pipeline.solid") && e.contains("twice"), "{e}");
        let product = BURNING
            .replace("product: \"products\"", "product: \"pbx\"")
            .replace("reactant: \"pbx\"", "reactant: \"products\"");
        let e = load_str("product.ron", &product, &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("pipeline.ice.reactions.0.product"), "{e}");
    }

    /// The piston without heat exchange (H = 0, the total energy
    /// conserved): the cells give the steel no temperature change, so both
    /// ways of handing it to the particles give the same bits over 30
    /// steps; with H = 10¹⁰ W/(m³·K) the air the piston compresses heats
    /// the steel and the two differ.
    #[test]
    fn without_heat_exchange_both_particle_heat_rules_give_the_same_bits() {
        let run = |set: &[&str]| -> (Vec<u64>, f64) {
            let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
            let loaded = load_str("piston_icempm.ron", PISTON, &set).unwrap();
            let mut built = icempm(&loaded.scenario);
            for _ in 0..30 {
                let dt = built.stable_dt().unwrap();
                built.advance(dt).unwrap();
            }
            let ps = built.mpm().particles();
            let bits = ps
                .temperature
                .iter()
                .chain(ps.position.iter().map(|x| &x[0]))
                .chain(ps.velocity.iter().map(|v| &v[0]))
                .map(|v| v.to_bits())
                .collect();
            let warmest = ps.temperature.iter().copied().fold(f64::MIN, f64::max);
            (bits, warmest)
        };
        let (nodes, _) = run(&["pipeline.particle_heat=Nodes"]);
        let (cell, warmest) = run(&["pipeline.particle_heat=Cell"]);
        assert_eq!(nodes, cell);
        assert_eq!(warmest, 300.0);
        let (nodes, warmest) = run(&[
            "pipeline.particle_heat=Nodes",
            "pipeline.ice.heat_exchange=1e10",
        ]);
        let (cell, _) = run(&[
            "pipeline.particle_heat=Cell",
            "pipeline.ice.heat_exchange=1e10",
        ]);
        assert!(warmest > 300.0, "{warmest}");
        assert_ne!(nodes, cell);
    }

    /// `thermal` on one of two solids turns on the conduction of the MPM
    /// side with that solid's properties at its particle material number
    /// (name order: `steel` 0, `steel_b` 1), and the run steps; on a fluid
    /// it is refused at its field.
    #[test]
    fn a_thermal_solid_conducts_and_a_thermal_fluid_is_refused() {
        let anchor = "rate: Jaumann),\n        ),\n    },\n    pipeline:";
        let text = two_steels().replace(
            anchor,
            "rate: Jaumann),\n            thermal: (conductivity: 45.0, specific_heat: 460.0),\n        ),\n    },\n    pipeline:",
        );
        assert!(text.contains("thermal"));
        let loaded = load_str("thermal.ron", &text, &[]).unwrap();
        let mut built = icempm(&loaded.scenario);
        let th = built.mpm().thermal_properties();
        assert_eq!(th.len(), 2);
        assert_eq!(
            (th[0].conductivity, th[0].specific_heat.constant()),
            (0.0, Some(0.0))
        );
        assert_eq!(
            (th[1].conductivity, th[1].specific_heat.constant()),
            (45.0, Some(460.0))
        );
        for _ in 0..5 {
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
        }
        let fluid = PISTON.replace(
            "\"air\": (eos: IdealGas(gamma: 1.4, cv: 717.5, rho0: 1.225)),",
            "\"air\": (eos: IdealGas(gamma: 1.4, cv: 717.5, rho0: 1.225), thermal: (conductivity: 0.026)),",
        );
        assert!(fluid.contains("thermal"));
        let e = load_str("fluid.ron", &fluid, &[]).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("materials.air.thermal"), "{e}");
        assert!(e.message.contains("not a `solid`"), "{e}");
        assert!(e.position.is_some(), "{e}");
    }

    /// A solid whose pressure does not depend on its energy (the piston's
    /// Murnaghan steel, t_ref 300 K) may start at another temperature in
    /// IceMpm: its particles carry it (the Ice pipeline refuses such a
    /// region, whose cells would keep the EOS's 300 K). The piston starts
    /// at 450 K: from the start (the first output) its cells and the air's
    /// trace inside it are at 450 K, its particles hold it over 20 steps
    /// (no heat exchange), and the run is the shipped one's in everything
    /// but the temperature: the particle positions the same to 10 nm (the
    /// air's trace inside the steel, held at the steel's temperature, is
    /// all that differs; 10⁻¹⁰ m measured).
    #[test]
    fn a_murnaghan_solid_starts_at_the_temperature_its_particles_carry() {
        use brisance_core::Solver;
        let steps = |text: &str| {
            let loaded = load_str("hot_piston.ron", text, &[]).unwrap();
            let mut built = icempm(&loaded.scenario);
            // Cell 55 lies inside the piston (50–60 mm).
            let data = built
                .cell_data(&["temperature_1".into(), "temperature_2".into()])
                .unwrap();
            let start = (data.fields[0].1[55], data.fields[1].1[55]);
            for _ in 0..20 {
                let dt = built.stable_dt().unwrap();
                built.advance(dt).unwrap();
            }
            let ps = built.mpm().particles();
            (ps.temperature.clone(), ps.position.clone(), start)
        };
        let hot = PISTON.replace(
            "velocity: (100.0, 0.0, 0.0), temperature: 300.0)",
            "velocity: (100.0, 0.0, 0.0), temperature: 450.0)",
        );
        assert_ne!(hot, PISTON);
        let (t_hot, x_hot, start_hot) = steps(&hot);
        let (t_cold, x_cold, start_cold) = steps(PISTON);
        for (start, t) in [(start_hot, 450.0), (start_cold, 300.0)] {
            assert!(
                (start.0 - t).abs() < 1e-6 && (start.1 - t).abs() < 1e-6,
                "air trace and steel in cell 55 at the start: {start:?}, not {t} K"
            );
        }
        assert!(t_hot.iter().all(|&t| t == 450.0), "{t_hot:?}");
        assert!(t_cold.iter().all(|&t| t == 300.0), "{t_cold:?}");
        let moved = x_hot
            .iter()
            .zip(&x_cold)
            .map(|(a, b)| (a[0] - b[0]).abs())
            .fold(0.0, f64::max);
        assert!(moved < 1e-8, "positions differ by up to {moved:e} m");
    }

    /// A QM-100 block as particles (the library's Murnaghan reactant with
    /// a hypoelastic model) in its products at 1 GPa, JWL++ reaction.
    const BURNING: &str = r#"Scenario(
    name: "burning_block",
    domain: (lower: (0.0, 0.0, 0.0), upper: (0.04, 0.001, 0.001), cells: (40, 1, 1)),
    boundaries: (x_low: Reflective, x_high: Reflective),
    time: (end: 1.0e-6),
    materials: {
        "products": (library: "qm100_products"),
        "pbx": (
            library: "qm100_reactant",
            model: Hypoelastic(shear_modulus: 1.0e9, pressure: Linear(bulk_modulus: 0.98e9), rate: Jaumann),
        ),
    },
    pipeline: IceMpm(
        ice: (
            materials: ["products"],
            reactions: [(reactant: "pbx", product: "products", model: JwlPlusPlus(g: 9.1e-5, b: 1.0))],
        ),
        solid: "pbx",
        mpm: (shape_function: Linear, scheme: Musl, ppc: 2),
    ),
    initial: [
        (region: Everywhere, material: "products", state: (density: 500.0, pressure: 1.0e9)),
        (region: Box(min: (0.017, -1.0, -1.0), max: (0.023, 1.0, 1.0)), material: "pbx", state: (density: 1700.0424, temperature: 298.15)),
    ],
)"#;

    /// The burning block runs from a config: the reactant particles lose
    /// mass every step, and the mass of both frames is kept to round-off.
    #[test]
    fn a_solid_reactant_burns_from_a_config() {
        let loaded = load_str("burning.ron", BURNING, &[]).unwrap();
        let mut built = icempm(&loaded.scenario);
        let m0 = built.conservation_totals().mass;
        let reactant = |b: &brisance_couple::IceMpm| b.mpm().particles().mass.iter().sum::<f64>();
        let r0 = reactant(&built);
        for _ in 0..10 {
            let r = reactant(&built);
            let dt = built.stable_dt().unwrap();
            built.advance(dt).unwrap();
            assert!(reactant(&built) < r);
        }
        assert!(reactant(&built) < 0.99 * r0);
        let m = built.conservation_totals().mass;
        assert!((m - m0).abs() <= 1e-13 * m0, "{m:e} vs {m0:e}");
    }
}
