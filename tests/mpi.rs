//! `mpirun -np N brisance run CONFIG` (cargo feature `mpi`, docs/cluster.md):
//! a run of every pipeline (Fdm, Ice, Mpm, Peridynamics, Lattice, IceMpm,
//! FdmMpmBridge) on 2 and 4 ranks writes the bytes of the same run on one,
//! file for file; a restart may change the rank count; what the ICE and
//! the lattice cannot spread and impossible splits refuse with one clear
//! message instead of hanging.
//!
//! Needs `mpirun` (Open MPI) on the PATH: `cargo test --features mpi --test mpi`.
#![cfg(feature = "mpi")]

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_brisance");
const BLAST: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/blast3d.ron");
const ICE_RZ: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/ice_rz.ron");
const ICE_3D: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/ice_bubble3d.ron");
const ICE_BURN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/ice_burn_rz.ron");
const PD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/pd_fragment.ron");
const LATTICE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/lattice_impact.ron");
const MPM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/mpm_taylor.ron");
const ICE_MPM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/icempm_cylinder.ron");
const BRIDGE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/mpi/bridge_rz.ron");
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// `brisance run CONFIG --out OUT --quiet EXTRA…` on `ranks` ranks
/// (`mpirun`, oversubscribed where the machine has fewer cores), or as
/// one plain process for `ranks == 0`.
fn run(ranks: usize, config: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut cmd = if ranks == 0 {
        Command::new(BIN)
    } else {
        let mut c = Command::new("mpirun");
        c.args(["--allow-run-as-root", "--oversubscribe", "-np"])
            .arg(ranks.to_string())
            .arg(BIN);
        c
    };
    cmd.env_remove("BRISANCE_LOG")
        .arg("run")
        .arg(config)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .output()
        .expect("mpirun (Open MPI) and the brisance binary run")
}

fn succeeded(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what} failed: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every file under `dir`, by path relative to it.
fn files(dir: &Path) -> BTreeMap<PathBuf, PathBuf> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).expect("output folder is readable") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.insert(p.strip_prefix(dir).unwrap().to_path_buf(), p);
            }
        }
    }
    out
}

/// The summary (or the bridge's time split) without what depends on the
/// machine's speed or threads.
fn summary_without_timing(path: &Path) -> Value {
    let mut v: Value = serde_json::from_str(&fs::read_to_string(path).unwrap()).unwrap();
    let o = v.as_object_mut().expect("summary is an object");
    for key in [
        "wall_seconds",
        "throughput",
        "threads",
        "wall_split",
        "fdm_seconds",
        "mpm_seconds",
    ] {
        o.remove(key);
    }
    v
}

/// Asserts that the outputs in `a` and `b` are the same bytes: every file
/// but `summary.json` (compared without its timing fields) and the
/// checkpoints (whose solver state and scenario are compared; the run
/// loop's part holds the compute time).
fn same_outputs(a: &Path, b: &Path, what: &str) {
    let (fa, fb) = (files(a), files(b));
    assert_eq!(
        fa.keys().collect::<Vec<_>>(),
        fb.keys().collect::<Vec<_>>(),
        "{what}: the same files"
    );
    assert!(fa.len() > 10, "{what}: outputs written");
    for (rel, pa) in &fa {
        let pb = &fb[rel];
        let name = rel.to_string_lossy();
        if name == "summary.json" || name == "time_split.json" {
            assert_eq!(
                summary_without_timing(pa),
                summary_without_timing(pb),
                "{what}: {name}"
            );
        } else if name.ends_with(".bin") {
            let (ca, cb) = (
                brisance::io::read_checkpoint(pa).unwrap(),
                brisance::io::read_checkpoint(pb).unwrap(),
            );
            assert!(
                ca.solver_state == cb.solver_state,
                "{what}: {name} solver state"
            );
            assert_eq!(ca.scenario_ron, cb.scenario_ron, "{what}: {name}");
        } else {
            assert!(
                fs::read(pa).unwrap() == fs::read(pb).unwrap(),
                "{what}: {name} differs"
            );
        }
    }
}

/// Runs `config` on one rank and on 2 and 4, and compares the outputs.
fn same_bytes_on_two_and_four_ranks(config: &str) {
    same_bytes_on_two_and_four_ranks_with(config, &[]);
}

/// [`same_bytes_on_two_and_four_ranks`] with `extra` arguments (`--set`).
fn same_bytes_on_two_and_four_ranks_with(config: &str, extra: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one");
    succeeded(&run(0, Path::new(config), &one, extra), "one rank");
    for ranks in [2, 4] {
        let out = tmp.path().join(format!("np{ranks}"));
        succeeded(&run(ranks, Path::new(config), &out, extra), "mpirun");
        same_outputs(
            &one,
            &out,
            &format!("{config} {extra:?}: {ranks} ranks against one"),
        );
    }
}

#[test]
fn fdm_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks(BLAST);
}

/// The ICE on rings (three materials, a JWL++ detonation, outflow faces
/// that book what leaves), in 3D (two gases, symmetry, inflow, both
/// outflow faces and a periodic pair), and on rings with a surface burn
/// (`Deflagration`, whose surface is found over the whole grid from what
/// every rank gives).
#[test]
fn ice_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks(ICE_RZ);
    same_bytes_on_two_and_four_ranks(ICE_3D);
    same_bytes_on_two_and_four_ranks(ICE_BURN);
}

/// The `Patches` VTK layout: each rank writes the pieces of its own
/// patches (rank 0 all of ICE–MPM's, whose every rank holds the whole
/// fluid), and the files are those of one rank.
#[test]
fn patch_pieces_on_two_and_four_ranks_are_the_bytes_of_one() {
    let pieces = ["--set", "outputs.vtk_layout=Patches"];
    same_bytes_on_two_and_four_ranks_with(BLAST, &pieces);
    same_bytes_on_two_and_four_ranks_with(ICE_RZ, &pieces);
    same_bytes_on_two_and_four_ranks_with(ICE_MPM, &pieces);
}

/// Peridynamics: a detonating tube whose wall tears into fragments, with
/// contacts and the products' artificial viscosity (the rows in which
/// bonds break cross between ranks).
#[test]
fn peridynamics_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks(PD);
}

/// MPM: a copper rod hitting a wall (Johnson–Cook plasticity, heating,
/// bulk viscosity, cpGIMP) under each update scheme, and with the ΔF̄
/// averaging (whose G2P runs on every rank, the stress update split);
/// particle gauges and particle output included.
#[test]
fn mpm_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks(MPM);
    for scheme in ["Usf", "Usl"] {
        let set = format!("pipeline.scheme={scheme}");
        same_bytes_on_two_and_four_ranks_with(MPM, &["--set", &set]);
    }
    same_bytes_on_two_and_four_ranks_with(MPM, &["--set", "pipeline.anti_locking=FBar"]);
}

/// The coupled pipelines: ICE–MPM (a detonating cylinder test on rings:
/// reaction, three fluids, copper particles, particle gauges) and the
/// FDM–MPM bridge (activation, particles created and inflow deposited at the
/// interface, a steel disc), each rank holding the whole grid and every
/// particle and updating its share of the particles.
#[test]
fn the_coupled_pipelines_on_two_and_four_ranks_write_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks(ICE_MPM);
    same_bytes_on_two_and_four_ranks(BRIDGE);
}

/// An MPM particle whose update fails on one rank's share stops every
/// rank with the message of one rank, naming the same particle.
#[test]
fn an_mpm_failure_on_one_rank_stops_all_with_the_message_of_one() {
    // The rod at 20 km/s against the wall, at a Courant number of 0.9,
    // inverts a particle's volume in its second step of the bare scheme
    // (no bulk viscosity). (At the file's 0.4 the particles that cross the
    // wall are mirrored back and the rod splashes out through the open
    // faces.)
    let sets = [
        "--set",
        "pipeline.bulk_viscosity=Off",
        "--set",
        "time.cfl=0.9",
        "--set",
        r#"initial=[(region: Cylinder(base: (0.0, 0.0, 0.0), axis: (0.0, 0.0, 1.0), radius: 0.00381, length: 0.0254), material: "copper", state: (density: 8930.0, velocity: (0.0, 0.0, -20000.0), temperature: 300.0))]"#,
    ];
    let tmp = tempfile::tempdir().unwrap();
    let one = run(0, Path::new(MPM), &tmp.path().join("one"), &sets);
    assert!(!one.status.success(), "the run should fail");
    let err = String::from_utf8_lossy(&one.stderr).into_owned();
    let line = err
        .lines()
        .find(|l| l.contains("error:"))
        .unwrap_or_else(|| panic!("an error line in:\n{err}"))
        .to_string();
    assert!(line.contains("particle"), "{line}");
    for ranks in [2, 4] {
        let out = run(
            ranks,
            Path::new(MPM),
            &tmp.path().join(format!("np{ranks}")),
            &sets,
        );
        fails_once_with(&out, &line);
    }
}

/// The lattice: two materials whose springs break, yield and carry
/// dashpots (the general passes, velocity Verlet); one material without
/// spring state (the row-stencil passes, explicit Euler); and in 3D.
#[test]
fn the_lattice_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks(LATTICE);
    same_bytes_on_two_and_four_ranks_with(
        LATTICE,
        &[
            "--set",
            r#"pipeline.materials={"hmx": (young: 25.325e9, conductivity: 0.4)}"#,
            "--set",
            r#"initial=[(region: Box(min: (0.0, 0.0, -1.0), max: (0.5e-3, 0.3e-3, 1.0)), material: "hmx", state: (density: 1580.0, pressure: 1.0e5, velocity: (-300.0, 0.0, 0.0)))]"#,
            "--set",
            "pipeline.integrator=ExplicitEuler",
        ],
    );
    same_bytes_on_two_and_four_ranks_with(
        LATTICE,
        &[
            "--set",
            "pipeline.dimension=Three",
            "--set",
            "domain.upper=(0.5e-3, 0.3e-3, 0.2e-3)",
        ],
    );
}

/// Runs `config` on one rank, then on two ranks to step `stop` and on
/// four from that step's checkpoint, and compares what both wrote.
fn restart_on_other_ranks(config: &str, stop: u64) {
    restart_on_other_ranks_with(config, stop, &[]);
}

/// [`restart_on_other_ranks`] with `extra` arguments (`--set`) for both
/// parts of the restarted run.
fn restart_on_other_ranks_with(config: &str, stop: u64, extra: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one");
    succeeded(&run(0, Path::new(config), &one, &[]), "one rank");
    let out = tmp.path().join("restarted");
    let max = format!("time.max_steps={stop}");
    let first = [&["--set", max.as_str()][..], extra].concat();
    succeeded(
        &run(2, Path::new(config), &out, &first),
        "two ranks to the stop",
    );
    let ck = out
        .join("checkpoints")
        .join(format!("checkpoint_{stop:08}.bin"));
    // The stopped run wrote its last state as an extra output; the
    // continued run writes the rest over it.
    let ck_arg = ck.to_string_lossy().into_owned();
    let second = [&["--restart", ck_arg.as_str()][..], extra].concat();
    succeeded(
        &run(4, Path::new(config), &out, &second),
        "four ranks from the checkpoint",
    );
    for rel in files(&one).keys() {
        let name = rel.to_string_lossy();
        if name.ends_with(".bin") || name == "summary.json" {
            continue;
        }
        if name == "time_split.json" {
            assert_eq!(
                summary_without_timing(&one.join(rel)),
                summary_without_timing(&out.join(rel)),
                "{config} restarted on other ranks: {name}"
            );
            continue;
        }
        assert!(
            fs::read(one.join(rel)).unwrap() == fs::read(out.join(rel)).unwrap(),
            "{config} restarted on other ranks: {name} differs"
        );
    }
}

#[test]
fn a_restart_may_change_the_rank_count() {
    restart_on_other_ranks(BLAST, 10);
    restart_on_other_ranks(ICE_RZ, 40);
    restart_on_other_ranks(PD, 40);
    restart_on_other_ranks(LATTICE, 20);
    restart_on_other_ranks(MPM, 40);
    restart_on_other_ranks(ICE_MPM, 40);
    // After the bridge's activation (about step 117).
    restart_on_other_ranks(BRIDGE, 200);
}

/// Checkpoints written per patch (each rank its own patches' files,
/// nothing gathered) restart on another rank count too, and the run goes
/// on with the bits of one rank.
#[test]
fn a_checkpoint_written_per_patch_restarts_on_another_rank_count() {
    let patches = ["--set", "outputs.checkpoint_layout=Patches"];
    restart_on_other_ranks_with(BLAST, 10, &patches);
    restart_on_other_ranks_with(ICE_RZ, 40, &patches);
}

/// Stderr of a failed run, checked to carry `message` exactly once.
fn fails_once_with(out: &Output, message: &str) {
    assert!(!out.status.success(), "the run should fail");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.matches(message).count(),
        1,
        "one message `{message}` expected in:\n{err}"
    );
}

/// A run that fails some steps in (streams colliding under the bare
/// scheme, as in `tests/cli.rs`) rewinds, on every rank, its own
/// snapshot (nothing gathered) and writes the state before the failed
/// step: the outputs of 2 and 4 ranks are those of one, the last field
/// output included.
#[test]
fn a_failed_step_leaves_the_last_good_state_of_one_rank() {
    let sod = Path::new(ROOT).join("configs/sod.ron");
    let sets = [
        "--set",
        "domain.cells=(200,1,1)",
        "--set",
        "domain.patches=(4,1,1)",
        "--set",
        "pipeline.limiter=Off",
        "--set",
        "pipeline.viscosity=Off",
        "--set",
        r#"initial=[(region: Everywhere, material: "gas", state: (density: 1.0, velocity: (1.35, 0, 0), pressure: 0.6)), (region: HalfSpace(point: (0.5, 0, 0), normal: (1, 0, 0)), material: "gas", state: (density: 0.125, velocity: (-1.35, 0, 0), pressure: 0.6))]"#,
    ];
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one");
    let out = run(0, &sod, &one, &sets);
    assert!(!out.status.success(), "the run should fail");
    let vtk = |dir: &Path| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = files(&dir.join("vtk")).into_keys().collect();
        v.sort();
        v
    };
    assert!(vtk(&one).len() >= 2, "the last good state is written");
    for ranks in [2, 4] {
        let dir = tmp.path().join(format!("np{ranks}"));
        let out = run(ranks, &sod, &dir, &sets);
        assert!(
            !out.status.success(),
            "the run on {ranks} ranks should fail"
        );
        assert_eq!(vtk(&one), vtk(&dir), "{ranks} ranks: the same snapshots");
        for rel in vtk(&one)
            .iter()
            .map(|f| Path::new("vtk").join(f))
            .chain([PathBuf::from("conservation.csv"), PathBuf::from("sod.pvd")])
        {
            assert!(
                fs::read(one.join(&rel)).unwrap() == fs::read(dir.join(&rel)).unwrap(),
                "{ranks} ranks: {} differs",
                rel.display()
            );
        }
    }
}

/// The lattice's implicit integrators on ranks: the force, commit and
/// volume passes in slabs, the assembly and the linear solve over every
/// node on every rank (each holds every node), so the impact writes the
/// bytes of one rank.
#[test]
fn the_implicit_lattice_on_two_and_four_ranks_writes_the_bytes_of_one() {
    for integrator in ["ImplicitEuler", "ImplicitRk2"] {
        same_bytes_on_two_and_four_ranks_with(
            LATTICE,
            &[
                "--set",
                &format!("pipeline.integrator={integrator}"),
                "--set",
                "pipeline.time_step=1e-9",
            ],
        );
    }
}

/// The ICE's implicit pressure on ranks: each outer iteration gathers the
/// cells' coefficients and divergences from their owners and every rank
/// solves the whole grid's system, so the 3D bubble, made a low-Mach one
/// (helium at 1.05 bar, air coming in at 10 m/s), writes the bytes of one
/// rank over its ten implicit steps.
#[test]
fn the_implicit_ice_pressure_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks_with(
        ICE_3D,
        &[
            "--set",
            "pipeline.pressure=Implicit(tolerance: 1e-9)",
            "--set",
            "initial.1.state=(density: 0.17, pressure: 1.05e5)",
            "--set",
            r#"boundaries.y_low=Fixed(material: "air", density: 1.2, velocity: (0.0, 10.0, 0.0), pressure: 1.0e5)"#,
            "--set",
            "time.end=2e-3",
        ],
    );
}

/// Viscosity and heat conduction spread over the ranks: the 3D bubble with
/// both gases viscous and conducting (strongly enough that the viscous
/// limit sets the step), its outflow faces booking the tractions and heat
/// fluxes that cross them.
#[test]
fn viscous_conducting_ice_on_two_and_four_ranks_writes_the_bytes_of_one() {
    same_bytes_on_two_and_four_ranks_with(
        ICE_3D,
        &[
            "--set",
            r#"pipeline.transport={"air": (viscosity: 20.0, thermal_conductivity: 50.0), "helium": (viscosity: 20.0, thermal_conductivity: 300.0)}"#,
        ],
    );
}

#[test]
fn more_ranks_than_patches_is_an_error() {
    let tmp = tempfile::tempdir().unwrap();
    let out = run(
        2,
        Path::new(BLAST),
        &tmp.path().join("split"),
        &["--set", "domain.patches=(1,1,1)"],
    );
    fails_once_with(&out, "2 ranks for 1 patches");
}
