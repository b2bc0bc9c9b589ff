use clap::{Parser, Subcommand};
use shadowfocus_cli::cli;
use shadowfocus_cli::cli::fit::FitOptions;
use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "shadowfocus", version, about = "Exact, fast focusing of shadow maps")]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Focus bodies H = hull(V ∪ l) ∩ S ∩ L for JSON-lines cases.
    Body {
        /// Input file, or - for standard input.
        #[arg(default_value = "-")]
        input: String,
        /// Time every case (excluding parsing) and print one JSON summary line.
        #[arg(long)]
        bench: bool,
        /// Print only the input lines whose body the certified float path
        /// answers (a case set for measuring that path alone).
        #[arg(long, conflicts_with = "bench")]
        float_path_cases: bool,
    },
    /// Shadow-map matrices for JSON-lines cases.
    Fit {
        #[command(flatten)]
        options: FitOptions,
        /// Input file, or - for standard input.
        #[arg(default_value = "-")]
        input: String,
        /// Time every case and print one JSON summary line.
        #[arg(long)]
        bench: bool,
        /// With --bench and one split: time the frustum, the body and the
        /// map's fit apart, as well as the whole fit.
        #[arg(long, requires = "bench")]
        phases: bool,
    },
    /// Render a built-in scene (or a .gltf/.glb file) with one method.
    Render {
        /// Built-in scene name or glTF file.
        #[arg(long)]
        scene: String,
        #[command(flatten)]
        options: FitOptions,
        /// Image size, WxH.
        #[arg(long, default_value = "960x540", value_parser = cli::render::parse_size)]
        size: (u32, u32),
        #[command(flatten)]
        overrides: cli::overrides::Overrides,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
    },
    /// A directional light swept over elevations × azimuths around the
    /// camera's view direction, every method at each: sweep.csv, sweep.json,
    /// plots of aliasing and mismatch against azimuth, the worst
    /// configurations on a contact sheet.
    Sweep {
        #[command(flatten)]
        options: cli::sweep::SweepOptions,
    },
    /// A camera path through a static scene: per-frame metrics and how much the shadows flicker
    /// (temporal.json, frames.csv, strip.png).
    Animate {
        #[command(flatten)]
        options: cli::animate::AnimateOptions,
    },
    /// Run time against error: scenes × methods × splits × resolutions, skip plan on/off, numerical stress.
    Bench {
        #[command(flatten)]
        options: cli::bench::BenchOptions,
    },
    /// Render every built-in scene with every method at one texel budget.
    Demo {
        /// Output folder.
        #[arg(long, default_value = "out/demo")]
        out: PathBuf,
        /// Image size, WxH.
        #[arg(long, default_value = "640x360", value_parser = cli::render::parse_size)]
        size: (u32, u32),
        /// Texels per side of a single map; four splits get half each.
        #[arg(long, default_value_t = 1024)]
        resolution: u32,
        /// Scenes to render (default: all built-in scenes).
        #[arg(long, value_delimiter = ',')]
        scenes: Vec<String>,
        #[command(flatten)]
        overrides: cli::overrides::Overrides,
    },
}

fn open(input: &str) -> io::Result<Box<dyn BufRead>> {
    if input == "-" {
        Ok(Box::new(BufReader::new(io::stdin())))
    } else {
        let f = File::open(PathBuf::from(input)).map_err(|e| io::Error::new(e.kind(), format!("cannot open {input}: {e}")))?;
        Ok(Box::new(BufReader::new(f)))
    }
}

/// A closed output pipe (`… | head`) ends the run quietly.
fn quiet_pipe(r: io::Result<usize>) -> Result<usize, String> {
    match r {
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(0),
        r => r.map_err(|e| e.to_string()),
    }
}

fn failures(failed: usize) -> Result<bool, String> {
    if failed > 0 {
        eprintln!("{failed} case(s) failed");
    }
    Ok(failed == 0)
}

fn run(command: Command) -> Result<bool, String> {
    let io_err = |e: io::Error| e.to_string();
    match command {
        Command::Body { input, bench, float_path_cases } => {
            let input = open(&input).map_err(io_err)?;
            if bench {
                println!("{}", cli::body::bench(input).map_err(io_err)?);
                return Ok(true);
            }
            if float_path_cases {
                return failures(quiet_pipe(cli::body::float_path_cases(input, BufWriter::new(io::stdout().lock())))?);
            }
            failures(quiet_pipe(cli::body::run(input, BufWriter::new(io::stdout().lock())))?)
        }
        Command::Fit { options, input, bench, phases } => {
            if options.sdsm {
                return Err(
                    "--sdsm measures the visible depth range on a rendered frame: use it with render, demo, sweep or animate".into()
                );
            }
            if options.visible_receivers || options.receiver_boxes {
                return Err("--receiver-boxes and --visible-receivers take a rendered scene's receivers: use them with render or sweep (--receiver-boxes with animate too)".into());
            }
            let settings = options.settings()?;
            let input = open(&input).map_err(io_err)?;
            if phases {
                if settings.splits.count != 1 {
                    return Err("--phases times one map per case: use it without --splits (or with --splits 1)".into());
                }
                println!("{}", cli::fit::phases(input, &settings).map_err(io_err)?);
                return Ok(true);
            }
            if bench {
                println!("{}", cli::fit::bench(input, &settings).map_err(io_err)?);
                return Ok(true);
            }
            failures(quiet_pipe(cli::fit::run(input, BufWriter::new(io::stdout().lock()), &settings))?)
        }
        Command::Render { scene, options, size, overrides, out } => {
            let scene = shadowfocus_cli::render::load_scene(&scene).map_err(|e| e.to_string())?;
            let frame = cli::overrides::Frame::with(&scene, &overrides)?;
            let mut renderer = shadowfocus_cli::render::Renderer::from_env().map_err(|e| e.to_string())?;
            let result = cli::render::render_frame_to(&mut renderer, &scene, &frame, &options, size, &out)?;
            println!("{}", serde_json::to_string(&result.metrics).map_err(|e| e.to_string())?);
            Ok(true)
        }
        Command::Animate { options } => {
            println!("{}", cli::animate::animate(&options)?);
            Ok(true)
        }
        Command::Bench { options } => {
            println!("{}", cli::bench::run(&options)?);
            Ok(true)
        }
        Command::Sweep { options } => {
            let summary = cli::sweep::run(&options)?;
            eprintln!("wrote {} configurations to {}", summary.rows.len(), options.out.join("sweep.csv").display());
            Ok(true)
        }
        Command::Demo { out, size, resolution, scenes, overrides } => {
            let scenes =
                if scenes.is_empty() { shadowfocus_cli::render::BUILTIN_SCENES.iter().map(|s| s.to_string()).collect() } else { scenes };
            let summary = cli::render::demo(&out, size, resolution, &scenes, &overrides)?;
            eprintln!(
                "wrote {} renders and {}",
                summary["results"].as_array().map_or(0, |r| r.len()),
                out.join("contact_sheet.png").display()
            );
            Ok(true)
        }
    }
}

fn main() -> ExitCode {
    match run(Args::parse().command) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
