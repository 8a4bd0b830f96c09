//! The `brisance` command line: run, check and list.

use std::path::PathBuf;
use std::process::ExitCode;

use brisance::compose::{self, load::DEFAULT_SCENARIO_NAME, registry, RunOptions};
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
        /// Continue from a checkpoint written by an earlier run.
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
}

fn load(
    config: Option<&PathBuf>,
    sets: &[String],
) -> Result<compose::LoadedScenario, compose::ConfigError> {
    match config {
        Some(path) => compose::load_file(path, sets),
        None => compose::load_str(DEFAULT_SCENARIO_NAME, compose::DEFAULT_SCENARIO, sets),
    }
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("BRISANCE_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    match cli.command {
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
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            let out_dir = out.unwrap_or_else(|| {
                compose::run::default_out_dir(config.as_deref(), &loaded.scenario.name)
            });
            let opts = RunOptions {
                out_dir: out_dir.clone(),
                restart,
                progress: !quiet,
            };
            match compose::run(&loaded, &opts) {
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
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
    }
}
