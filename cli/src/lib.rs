//! The crowdgaze command-line tool as a library: the commands of the `crowdgaze` binary and
//! the pieces they are made of (trajectory files, BVH files, pictures), so that tests can
//! use them directly.

pub mod bvh;
pub mod cli;
pub mod commands;
pub mod lookup;
pub mod output;
pub mod plot;
pub mod sim;
pub mod skeleton;
pub mod traj;

/// Runs a parsed command line.
pub fn run(cli: &cli::Cli) -> anyhow::Result<()> {
    match &cli.command {
        cli::Command::Demo(args) => commands::demo(args),
        cli::Command::Annotate(args) => commands::annotate(args),
        cli::Command::Plot(args) => commands::plot(args),
        cli::Command::Bvh(args) => commands::bvh(args),
    }
}
