//! The `qjulia` binary: parses the command line and maps errors to CONTRACT.md's exit codes.

mod cli;

use std::process::ExitCode;

use clap::{CommandFactory, Parser};

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    let result = match &cli.command {
        Some(cli::Command::Render(args)) => cli::render(args),
        Some(cli::Command::Info) => cli::info(),
        Some(cli::Command::Explore(_)) => Err(anyhow::anyhow!(
            "the explorer is not built yet; use `qjulia render`"
        )),
        None => {
            // No explorer yet, so no subcommand means help, on stdout, exit 0.
            let _ = cli::Cli::command().print_help();
            return ExitCode::SUCCESS;
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            let code = e
                .downcast_ref::<qjulia::Error>()
                .map_or(1, qjulia::Error::exit_code);
            ExitCode::from(code as u8)
        }
    }
}
