//! The `geodesics` command-line tool.
//!
//! ```text
//! geodesics info [MESH] [--weld] [--json]
//! geodesics distance [MESH] [--source V ...] [--source-point FACE:B0,B1,B2]
//!     [--source-edge A,B:T] [--algorithm vtp] [--max-distance D] [--weld]
//!     [--output FILE] [--stats FILE.json] [--threads T] [--lambda L]
//! geodesics path [MESH] --target V [--source V ...] [--algorithm vtp|mmp]
//!     [--output FILE.obj|.csv|.json]
//! ```
//!
//! Without a mesh file both run on a built-in procedural mesh.
//!
//! Exit status: 0 on success, 2 on a usage error, 1 on bad input (with a
//! one-line message that names the file and the defect).

mod distance;
mod info;
mod input;
mod path;
mod progress;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Exact geodesic distances on triangle meshes.
#[derive(Parser, Debug)]
#[command(name = "geodesics", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print a mesh's statistics: size, topology, defects, anisotropy.
    Info(info::InfoArgs),
    /// Compute geodesic distances from sources to every vertex.
    Distance(distance::DistanceArgs),
    /// Trace the exact shortest path from the nearest source to a vertex.
    Path(path::PathArgs),
}

/// Writes to stdout; a closed pipe (`geodesics info | head`) is not an error.
pub(crate) fn print_stdout(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

/// The chain of causes joined in one line, no backtrace. A cause whose
/// text the message already ends with is left out: an error that prints
/// its source and also returns it (`IoError::Io` does) said it twice.
fn one_line(err: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in err.chain() {
        let text = cause.to_string().replace('\n', " ");
        if message.ends_with(&text) {
            continue;
        }
        if !message.is_empty() {
            message.push_str(": ");
        }
        message.push_str(&text);
    }
    message
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(args) => info::run(&args),
        Command::Distance(args) => distance::run(&args),
        Command::Path(args) => path::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", one_line(&err));
            ExitCode::from(1)
        }
    }
}
