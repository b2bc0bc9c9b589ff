use clap::{Parser, Subcommand};
use shadowfocus::cli;
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
    /// Focus bodies H = hull(V ∪ l) ∩ S ∩ L for JSON-lines cases (FILE or - for stdin).
    Body {
        /// Input file, or - for standard input.
        #[arg(default_value = "-")]
        input: String,
        /// Time every case (excluding parsing) and print one JSON summary line.
        #[arg(long)]
        bench: bool,
    },
}

fn open(input: &str) -> io::Result<Box<dyn BufRead>> {
    if input == "-" {
        Ok(Box::new(BufReader::new(io::stdin())))
    } else {
        Ok(Box::new(BufReader::new(File::open(PathBuf::from(input)).map_err(|e| {
            io::Error::new(e.kind(), format!("cannot open {input}: {e}"))
        })?)))
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    let result: io::Result<bool> = (|| match args.command {
        Command::Body { input, bench } => {
            if bench {
                println!("{}", cli::body::bench(open(&input)?)?);
                Ok(true)
            } else {
                let failed = cli::body::run(open(&input)?, BufWriter::new(io::stdout().lock()))?;
                if failed > 0 {
                    eprintln!("{failed} case(s) failed");
                }
                Ok(failed == 0)
            }
        }
    })();
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
