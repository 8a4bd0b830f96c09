//! The `brisance` command line: run, check, list and remap.

use std::path::PathBuf;
use std::process::ExitCode;

use brisance::compose::{self, load::DEFAULT_SCENARIO_NAME, registry, RunOptions};
use brisance_grid::comm;
use clap::{Parser, Subcommand};

/// Simulation of explosions of energetic devices and their effect on
/// nearby structures.
#[derive(Parser)]
#[command(name = "brisance", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario (the built-in default when no CONFIG is given).
    Run {
        /// Scenario file (RON).
        config: Option<PathBuf>,
        /// Output directory (default: out/<config stem>/).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Override a field of the scenario by dotted path, e.g.
        /// `--set domain.cells=(800,1,1)`; may be repeated.
        #[arg(long = "set", value_name = "PATH=VALUE")]
        sets: Vec<String>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Continue from a checkpoint written by an earlier run; `latest`:
        /// the newest valid checkpoint in the output directory.
        #[arg(long)]
        restart: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Parse and validate a scenario and print the resolved pipeline.
    Check {
        /// Scenario file (RON).
        config: PathBuf,
        /// Overrides, as for `run`.
        #[arg(long = "set", value_name = "PATH=VALUE")]
        sets: Vec<String>,
    },
    /// List every equation of state, material, reaction model and pipeline.
    List,
    /// Run a 1D TNT detonation in air with program burn (seed 001 §4.1,
    /// eqs 52–53) and remap it onto a 1D/2D/3D FDM grid as its initial
    /// state, conserving the charge's mass, energy and products mass
    /// (docs/physics/couple/remap.md). Writes remap.bin (the initial
    /// state), remap.vti and profile.csv into OUT.
    Remap(RemapArgs),
}

/// Symmetry of the 1D detonation.
#[derive(Clone, Copy, clap::ValueEnum)]
enum RemapSymmetry {
    /// Slab (onto a 1D grid).
    Planar,
    /// Cylinder (onto a 2D grid).
    Cylindrical,
    /// Sphere (onto a 3D grid).
    Spherical,
}

#[derive(clap::Args)]
struct RemapArgs {
    /// Symmetry of the charge.
    #[arg(long, value_enum)]
    symmetry: RemapSymmetry,
    /// Charge radius, m.
    #[arg(long)]
    charge_radius: f64,
    /// Outer radius of the 1D grid, m.
    #[arg(long)]
    radius_1d: f64,
    /// Cells of the 1D grid.
    #[arg(long)]
    cells_1d: usize,
    /// Time to run the 1D detonation to, s (after the burn is complete).
    #[arg(long)]
    time: f64,
    /// Low corner of the target grid, m: x,y,z.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    lower: Vec<f64>,
    /// High corner of the target grid, m: x,y,z.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    upper: Vec<f64>,
    /// Cells of the target grid: nx,ny,nz (1 in unused directions).
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    cells: Vec<usize>,
    /// Charge centre, m: x,y,z.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_hyphen_values = true
    )]
    centre: Vec<f64>,
    /// Remap radius, m (default: the 1D grid's outer radius).
    #[arg(long)]
    radius: Option<f64>,
    /// Sub-cells per direction (default: ⌈Δx/h⌉ within [2, 16]).
    #[arg(long)]
    subsamples: Option<usize>,
    /// The target is an axisymmetric (r, z) grid (x = r from 0, y = z,
    /// one cell along z) of rings: a spherical charge centred on the axis
    /// (`--centre=0,z,0`).
    #[arg(long)]
    axisymmetric: bool,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
}

/// `brisance remap`: the 1D run, the remap and its files.
fn remap(a: &RemapArgs) -> Result<String, String> {
    use brisance::fdm::GasLaw;
    use brisance_couple::remap::{Charge, ChargeSymmetry};
    let symmetry = match a.symmetry {
        RemapSymmetry::Planar => ChargeSymmetry::Planar,
        RemapSymmetry::Cylindrical => ChargeSymmetry::Cylindrical,
        RemapSymmetry::Spherical => ChargeSymmetry::Spherical,
    };
    if !(a.time > 0.0 && a.time.is_finite()) {
        return Err(format!("--time = {} s must be positive", a.time));
    }
    for (name, len) in [
        ("--lower", a.lower.len()),
        ("--upper", a.upper.len()),
        ("--cells", a.cells.len()),
        ("--centre", a.centre.len()),
    ] {
        if len != 3 {
            return Err(format!(
                "{name} takes three comma-separated values, got {len}"
            ));
        }
    }
    let (lower, upper, cells, centre) = (
        [a.lower[0], a.lower[1], a.lower[2]],
        [a.upper[0], a.upper[1], a.upper[2]],
        [a.cells[0], a.cells[1], a.cells[2]],
        [a.centre[0], a.centre[1], a.centre[2]],
    );
    for d in 0..3 {
        if cells[d] == 0 || !(upper[d] > lower[d]) {
            return Err(format!(
                "--cells and --lower/--upper: direction {d} needs at least one cell and upper > lower"
            ));
        }
    }
    // The grid arguments are checked above, before the 1D run.
    let geometry = brisance::core::UniformGridGeometry {
        origin: lower,
        spacing: std::array::from_fn(|d| (upper[d] - lower[d]) / cells[d] as f64),
        cells,
    };
    let charge = Charge {
        explosive: "tnt".into(),
        symmetry,
        centre,
        radius: a.charge_radius,
        radius_1d: a.radius_1d,
        cells_1d: a.cells_1d,
        time: a.time,
        remap_radius: a.radius,
        subsamples: a.subsamples,
    };
    let coordinates = if a.axisymmetric {
        brisance::core::Geometry::Axisymmetric
    } else {
        brisance::core::Geometry::Cartesian
    };
    let (run, mapped) = charge
        .detonate_and_remap(geometry, coordinates)
        .map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    mapped
        .save(&a.out.join("remap.bin"))
        .map_err(|e| e.to_string())?;
    // Primitive fields for viewing.
    let gas = run.gas();
    let f = &mapped.fields;
    let n = geometry.cell_count();
    let prim: Vec<Vec<f64>> = (0..6)
        .map(|k| {
            (0..n)
                .map(|c| {
                    let rho = f[0][c];
                    let u = [f[1][c] / rho, f[2][c] / rho, f[3][c] / rho];
                    let y = f[5][c] / rho;
                    match k {
                        0 => rho,
                        1..=3 => u[k - 1],
                        4 => {
                            let ke = 0.5 * rho * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
                            gas.gas_pressure(rho, (f[4][c] - ke) / rho, y)
                        }
                        _ => y,
                    }
                })
                .collect()
        })
        .collect();
    let names = [
        "density",
        "velocity_x",
        "velocity_y",
        "velocity_z",
        "pressure",
        "products_mass_fraction",
    ];
    let data = brisance::core::CellData {
        geometry,
        fields: names.iter().map(|s| s.to_string()).zip(prim).collect(),
    };
    brisance::io::vti::write_vti(&a.out.join("remap.vti"), &data).map_err(|e| e.to_string())?;
    let mut csv = String::from("radius,density,velocity,pressure,products_mass_fraction\n");
    for (i, r) in run.radii().iter().enumerate() {
        let (rho, u, p, y) = run.state(i);
        csv.push_str(&format!("{r:e},{rho:e},{u:e},{p:e},{y:e}\n"));
    }
    brisance::io::write_atomic(&a.out.join("profile.csv"), csv.as_bytes())
        .map_err(|e| e.to_string())?;
    let r = mapped.report;
    let rel = |grid: f64, amb: f64, charge: f64| (grid - amb - charge) / charge;
    Ok(format!(
        "1D {} detonation: {} steps to t = {:e} s\nremap radius {} m, {} sub-cells per direction, {} symmetry plane(s), {} shell(s) merged, largest shell correction {:.3e}\ncharge: mass {:e} kg, energy {:e} J, products {:e} kg\nrelative change: mass {:.3e}, energy {:.3e}, products {:.3e}\noutputs in {}",
        ["planar", "cylindrical", "spherical"][usize::from(brisance_couple::remap::alpha_of(symmetry.into()))],
        run.steps(),
        run.time(),
        r.radius,
        r.subsamples,
        r.symmetry_planes,
        r.merged_shells,
        r.max_correction,
        r.charge.mass,
        r.charge.energy,
        r.charge.products,
        rel(r.grid_mass, r.ambient.mass, r.charge.mass),
        rel(r.grid_energy, r.ambient.energy, r.charge.energy),
        rel(r.grid_products, r.ambient.products, r.charge.products),
        a.out.display()
    ))
}

/// Loads a scenario and prints its warnings (`warning: file:line:col: ...`).
fn load(
    config: Option<&PathBuf>,
    sets: &[String],
) -> Result<compose::LoadedScenario, compose::ConfigError> {
    let loaded = match config {
        Some(path) => compose::load_file(path, sets),
        None => compose::load_str(DEFAULT_SCENARIO_NAME, compose::DEFAULT_SCENARIO, sets),
    }?;
    if comm::world().rank() == 0 {
        for w in &loaded.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(loaded)
}

fn main() -> ExitCode {
    // Under mpirun every rank runs this program; MPI stays initialised
    // until the session is dropped at the end of `main`.
    #[cfg(feature = "mpi")]
    let _mpi = brisance_grid::comm::mpi::init();
    install_panic_hook();
    // Warnings are the same on every rank: rank 0 says them.
    let level = if comm::world().rank() == 0 {
        "warn"
    } else {
        "error"
    };
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("BRISANCE_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level)),
        )
        .with_writer(std::io::stderr)
        .init();
    let code = run_command();
    let ranks = comm::world();
    if code == ExitCode::FAILURE && ranks.size() > 1 {
        // Stop every rank now: a rank that has not met the error (rank 0
        // alone writes the outputs) would otherwise wait for this one in
        // the next exchange. Rank 0 has printed the error; another rank
        // leaves rank 0 a moment to do so (and to end them all), then
        // says its own and ends them.
        if ranks.rank() != 0 {
            std::thread::sleep(std::time::Duration::from_secs(5));
        }
        ranks.abort(1);
    }
    code
}

/// Prints `message` as the error of this run: on rank 0 when the run
/// spans several ranks (they all meet the same error; see `main`), with
/// the rank on another rank.
fn report_error(message: &str) {
    let ranks = comm::world();
    match ranks.rank() {
        0 => eprintln!("error: {message}"),
        r => {
            // Only printed if rank 0 has not ended the job first.
            std::thread::sleep(std::time::Duration::from_secs(4));
            eprintln!("error (rank {r}): {message}");
        }
    }
}

/// The command line's command; its exit status.
fn run_command() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Remap(args) => match remap(&args) {
            Ok(text) => {
                println!("{text}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Command::List => {
            print!("{}", registry::listing());
            ExitCode::SUCCESS
        }
        Command::Check { config, sets } => match load(Some(&config), &sets) {
            Ok(loaded) => {
                println!(
                    "{}: ok\n{}",
                    loaded.file,
                    compose::build::describe(&loaded.scenario)
                );
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Run {
            config,
            out,
            sets,
            threads,
            restart,
            quiet,
        } => {
            if let Some(n) = threads {
                if n == 0 {
                    eprintln!("error: --threads must be at least 1");
                    return ExitCode::FAILURE;
                }
                if let Err(e) = rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build_global()
                {
                    eprintln!("error: cannot start {n} threads: {e}");
                    return ExitCode::FAILURE;
                }
            }
            let loaded = match load(config.as_ref(), &sets) {
                Ok(l) => l,
                Err(e) => {
                    report_error(&e.to_string());
                    return ExitCode::FAILURE;
                }
            };
            let out_dir = out.unwrap_or_else(|| {
                compose::run::default_out_dir(config.as_deref(), &loaded.scenario.name)
            });
            let rank = comm::world().rank();
            let opts = RunOptions {
                out_dir: out_dir.clone(),
                restart,
                progress: !quiet && rank == 0,
            };
            let stop = stop_on_signals();
            match compose::run_until_stopped(&loaded, &opts, &stop) {
                Ok(_) if rank != 0 => ExitCode::SUCCESS,
                Ok(s) => {
                    println!(
                        "{}: {} steps to t = {:e} s in {:.2} s wall on {} threads\n  throughput {:.3e} {}\n  relative mass change {:.3e}, relative energy change {:.3e}\n  outputs in {}",
                        s.scenario,
                        s.steps,
                        s.final_time,
                        s.wall_seconds,
                        s.threads,
                        s.throughput,
                        s.throughput_unit,
                        s.relative_mass_change,
                        s.relative_energy_change,
                        out_dir.display()
                    );
                    if let Some(line) = outflow_line(&s) {
                        println!("{line}");
                    }
                    if let Some(line) = wall_split_line(&s.wall_split, s.wall_seconds) {
                        println!("{line}");
                    }
                    for g in &s.safeguards {
                        println!("{}", safeguard_line(g));
                    }
                    for line in time_step_lines(&s) {
                        println!("{line}");
                    }
                    ExitCode::SUCCESS
                }
                Err(e @ compose::RunError::Interrupted { .. }) => {
                    // Every rank stopped after the same step.
                    if rank == 0 {
                        let args: Vec<String> = std::env::args().collect();
                        eprintln!(
                            "error: {e}; continue with: {}",
                            restart_command(&args, &out_dir)
                        );
                    }
                    ExitCode::from(EXIT_INTERRUPTED)
                }
                Err(e) => {
                    report_error(&e.to_string());
                    ExitCode::FAILURE
                }
            }
        }
    }
}

/// Exit status of a run stopped by SIGINT or SIGTERM (after its checkpoint).
const EXIT_INTERRUPTED: u8 = 130;

/// A flag that SIGINT and SIGTERM set, so the run stops after the step
/// under way; a second signal ends the program at once (status 1).
fn stop_on_signals() -> std::sync::Arc<std::sync::atomic::AtomicBool> {
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    #[cfg(unix)]
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        // The first call arms the exit on a second signal, the second
        // sets the flag; a failure leaves the signal's default action.
        let armed = signal_hook::flag::register_conditional_shutdown(signal, 1, stop.clone())
            .and_then(|_| signal_hook::flag::register(signal, stop.clone()));
        if let Err(e) = armed {
            tracing::warn!("cannot catch signal {signal}: {e}");
        }
    }
    stop
}

/// The command that continues an interrupted run: this one (the program
/// as it was invoked) with
/// `--restart latest` (replacing any `--restart`) and `--out` given, its
/// words quoted for a POSIX shell where needed.
fn restart_command(args: &[String], out_dir: &std::path::Path) -> String {
    let program = args.first().map_or("brisance", String::as_str);
    let mut words: Vec<String> = vec![program.to_string()];
    let mut rest = args.iter().skip(1);
    let mut has_out = false;
    while let Some(a) = rest.next() {
        if a == "--restart" {
            rest.next();
            continue;
        }
        if a.starts_with("--restart=") {
            continue;
        }
        has_out |= a == "--out" || a.starts_with("--out=");
        words.push(a.clone());
    }
    if !has_out {
        words.push("--out".into());
        words.push(out_dir.display().to_string());
    }
    words.push("--restart".into());
    words.push(compose::run::LATEST.into());
    words
        .iter()
        .map(|w| shell_word(w))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `w` as one POSIX shell word: as it is when it holds only safe
/// characters, otherwise in single quotes.
fn shell_word(w: &str) -> String {
    let safe = !w.is_empty()
        && w.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=,:+@%".contains(c));
    if safe {
        w.to_string()
    } else {
        format!("'{}'", w.replace('\'', "'\\''"))
    }
}

/// The one line a panic prints (unless `RUST_BACKTRACE` asks for the
/// backtrace): what failed, where, and where to report it.
fn panic_line(message: &str, location: Option<(&str, u32, u32)>) -> String {
    let place = location
        .map(|(file, line, col)| format!(" at {file}:{line}:{col}"))
        .unwrap_or_default();
    format!(
        "error: internal error (a bug in brisance {}): {message}{place}; please report it with the command and scenario at {}/issues (RUST_BACKTRACE=1 shows a backtrace)",
        env!("CARGO_PKG_VERSION"),
        env!("CARGO_PKG_REPOSITORY")
    )
}

/// Replaces the default panic message and backtrace by [`panic_line`],
/// unless `RUST_BACKTRACE` is set (and not `0`), which keeps Rust's own
/// message and backtrace. A panic still ends the program with a non-zero
/// status (101), and on several MPI ranks it stops them all either way.
fn install_panic_hook() {
    let verbose = std::env::var_os("RUST_BACKTRACE").is_some_and(|v| v != "0");
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if verbose {
            default(info);
        } else {
            let payload = info.payload();
            let message = payload
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("a panic without a message");
            let location = info.location().map(|l| (l.file(), l.line(), l.column()));
            eprintln!("{}", panic_line(message, location));
        }
        // The other ranks would wait for this one forever.
        let ranks = comm::world();
        if ranks.size() > 1 {
            ranks.abort(101);
        }
    }));
}

/// The summary's line on what left through the open boundaries, as
/// fractions of the initial totals, e.g.
/// `  left through open boundaries: mass 1.618e-2, energy 1.318e-1 of the initial`;
/// `None` where the solver does not book it. The relative changes above
/// already count it as kept.
fn outflow_line(s: &brisance::io::RunSummary) -> Option<String> {
    let o = s.outflow?;
    let share = |part: f64, whole: f64| part / whole.abs();
    Some(format!(
        "  left through open boundaries: mass {:.3e}, energy {:.3e} of the initial",
        share(o.mass, s.initial_totals.mass),
        share(o.energy, s.initial_totals.energy)
    ))
}

/// The summary's line on one safeguard, e.g.
/// `  positivity limiter acted on 12 of 123456 faces (9.720e-5)`.
fn safeguard_line(g: &brisance::io::Safeguard) -> String {
    let share = if g.checked > 0 {
        g.acted as f64 / g.checked as f64
    } else {
        0.0
    };
    format!(
        "  {} acted on {} of {} {} ({share:.3e})",
        g.name, g.acted, g.checked, g.unit
    )
}

/// The summary's lines on the time step, e.g.
/// `  time step: first 2.500e-7 s, smallest 1.000e-9 s at t = 7.500e-4 s, last 3.000e-8 s`
/// and, where the method says what sets it at the end,
/// `  last step set by: MPM particle 7 ...`; empty for a run without a step.
fn time_step_lines(s: &brisance::io::RunSummary) -> Vec<String> {
    let Some(t) = &s.time_step else {
        return Vec::new();
    };
    let mut lines = vec![format!(
        "  time step: first {:.3e} s, smallest {:.3e} s at t = {:.3e} s, last {:.3e} s",
        t.first, t.smallest, t.smallest_at, t.last
    )];
    if let Some(limit) = &t.limit {
        lines.push(format!("  last step set by: {limit}"));
    }
    lines
}

/// The summary's line on a coupled method's split of its wall time, e.g.
/// `  wall split: fdm 33.0 s (42 %), mpm 46.0 s (58 %)` (shares of the
/// whole run's wall time); `None` for a method with one part.
fn wall_split_line(parts: &[brisance::io::WallPart], wall_seconds: f64) -> Option<String> {
    if parts.is_empty() {
        return None;
    }
    let items: Vec<String> = parts
        .iter()
        .map(|p| {
            if wall_seconds > 0.0 {
                format!(
                    "{} {:.1} s ({:.0} %)",
                    p.part,
                    p.seconds,
                    100.0 * p.seconds / wall_seconds
                )
            } else {
                format!("{} {:.1} s", p.part, p.seconds)
            }
        })
        .collect();
    Some(format!("  wall split: {}", items.join(", ")))
}

#[cfg(test)]
mod tests {
    use super::{
        outflow_line, panic_line, restart_command, shell_word, time_step_lines, wall_split_line,
    };

    #[test]
    fn a_panic_is_one_line_saying_what_where_and_where_to_report() {
        let line = panic_line(
            "no entry found for key",
            Some(("crates/compose/src/bridge.rs", 343, 18)),
        );
        assert!(!line.contains('\n'), "{line}");
        assert!(line.starts_with("error: internal error"), "{line}");
        assert!(
            line.contains("no entry found for key at crates/compose/src/bridge.rs:343:18"),
            "{line}"
        );
        assert!(
            line.contains(&format!("{}/issues", env!("CARGO_PKG_REPOSITORY"))),
            "{line}"
        );
        assert!(line.contains("RUST_BACKTRACE=1"), "{line}");
        assert!(panic_line("boom", None).contains(": boom; please report"));
    }

    #[test]
    fn the_restart_command_is_the_run_with_restart_latest() {
        let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let out = std::path::Path::new("out/sod");
        assert_eq!(
            restart_command(&args(&["target/brisance", "run", "configs/sod.ron"]), out),
            "target/brisance run configs/sod.ron --out out/sod --restart latest"
        );
        assert_eq!(
            restart_command(
                &args(&[
                    "brisance",
                    "run",
                    "c.ron",
                    "--out",
                    "my out",
                    "--set",
                    "domain.cells=(8,1,1)",
                    "--restart",
                    "old.bin",
                ]),
                out
            ),
            "brisance run c.ron --out 'my out' --set 'domain.cells=(8,1,1)' --restart latest"
        );
        assert_eq!(shell_word("it's"), "'it'\\''s'");
    }
    use brisance::core::ConservationTotals;
    use brisance::io::{RunSummary, WallPart};

    #[test]
    fn the_outflow_line_gives_shares_of_the_initial_totals() {
        let totals = |mass, energy| ConservationTotals {
            mass,
            momentum: [0.0; 3],
            energy,
        };
        let mut s = RunSummary {
            scenario: "s".into(),
            pipeline: "p".into(),
            steps: 1,
            final_time: 1.0,
            wall_seconds: 1.0,
            throughput: 1.0,
            throughput_unit: "cell-updates/s".into(),
            initial_totals: totals(4.0, -8.0),
            final_totals: totals(4.0, -8.0),
            relative_mass_change: 0.0,
            relative_energy_change: 0.0,
            threads: 1,
            completed: true,
            stop_reason: None,
            outflow: None,
            wall_split: Vec::new(),
            safeguards: Vec::new(),
            time_step: None,
            warnings: Vec::new(),
        };
        assert_eq!(outflow_line(&s), None);
        assert!(time_step_lines(&s).is_empty());
        s.time_step = Some(brisance::io::TimeStepSummary {
            first: 2.5e-7,
            smallest: 1e-9,
            smallest_at: 7.5e-4,
            last: 3e-8,
            limit: None,
        });
        assert_eq!(
            time_step_lines(&s),
            ["  time step: first 2.500e-7 s, smallest 1.000e-9 s at t = 7.500e-4 s, last 3.000e-8 s"]
        );
        if let Some(t) = s.time_step.as_mut() {
            t.limit = Some("MPM particle 7".into());
        }
        assert_eq!(time_step_lines(&s)[1], "  last step set by: MPM particle 7");
        // 1 of 4 kg and 2 J of an initial −8 J (scaled by |E₀|).
        s.outflow = Some(totals(1.0, 2.0));
        assert_eq!(
            outflow_line(&s).as_deref(),
            Some("  left through open boundaries: mass 2.500e-1, energy 2.500e-1 of the initial")
        );
    }

    #[test]
    fn the_wall_split_line_names_each_part_with_its_share() {
        let parts = [
            WallPart {
                part: "fdm".into(),
                seconds: 33.0,
            },
            WallPart {
                part: "mpm".into(),
                seconds: 46.0,
            },
        ];
        assert_eq!(
            wall_split_line(&parts, 100.0).as_deref(),
            Some("  wall split: fdm 33.0 s (33 %), mpm 46.0 s (46 %)")
        );
        assert_eq!(
            wall_split_line(&parts, 0.0).as_deref(),
            Some("  wall split: fdm 33.0 s, mpm 46.0 s")
        );
        assert_eq!(wall_split_line(&[], 10.0), None);
    }
}
