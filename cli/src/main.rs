//! `crowdgaze`: the command-line tool. Errors are one line on standard error and exit code 1
//! (2 for a bad command line).

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = crowdgaze_cli::cli::Cli::parse();
    match crowdgaze_cli::run(&cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            // `{:#}` joins the context chain on one line.
            eprintln!("crowdgaze: error: {error:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
