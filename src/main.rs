//! The `qjulia` binary: parses the command line and maps errors to docs/CONTRACT.md's exit codes.

mod cli;

use std::process::ExitCode;

use clap::{CommandFactory, Parser};

fn main() -> ExitCode {
    // First, before any other thread exists (see its comment).
    qjulia::gpu::give_a_runtime_dir();
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version go to stdout as usual; a usage error is one line and exit 2.
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            let text = e.render().to_string();
            let mut lines = text.lines();
            let mut line = lines
                .next()
                .unwrap_or("error: bad command line")
                .to_string();
            if line.ends_with(':') {
                // The missing arguments, listed on the lines after.
                let listed: Vec<&str> = lines
                    .map_while(|l| Some(l.trim()).filter(|l| !l.is_empty()))
                    .collect();
                line = format!("{line} {}", listed.join(", "));
            }
            eprintln!("{line} (see qjulia --help)");
            return ExitCode::from(2);
        }
    };
    let result = match &cli.command {
        Some(cli::Command::Render(args)) => cli::render(args),
        Some(cli::Command::Merge(args)) => cli::merge(args),
        Some(cli::Command::Animate(args)) => cli::animate(args),
        Some(cli::Command::Render2d(args)) => cli::render2d(args),
        Some(cli::Command::Mesh(args)) => cli::mesh(args),
        Some(cli::Command::Info) => cli::info(),
        Some(cli::Command::Report(args)) => cli::report(args),
        Some(cli::Command::Explore(args)) => cli::explore(args),
        Some(cli::Command::GpuParams(args)) => cli::gpu_params(args),
        Some(cli::Command::Kernel(args)) => cli::kernel(args),
        Some(cli::Command::Schema(args)) => cli::schema(args),
        Some(cli::Command::Web(args)) => cli::web(args),
        None if qjulia::explore::display_available() => cli::explore(&cli::ExploreArgs::default()),
        None => {
            // No display to explore on: help, on stdout, exit 0.
            let _ = cli::Cli::command().print_help();
            return ExitCode::SUCCESS;
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", qjulia::error::one_line(&format!("{e:#}")));
            let code = e
                .downcast_ref::<qjulia::Error>()
                .map_or(1, qjulia::Error::exit_code);
            ExitCode::from(code as u8)
        }
    }
}
