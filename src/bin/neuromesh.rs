//! The `neuromesh` command line ([`neuromesh::cli`]).

fn main() -> std::process::ExitCode {
    std::process::ExitCode::from(neuromesh::cli::main(std::env::args_os(), true))
}
