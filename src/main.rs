//! The `surfkit` command (see `surfkit --help`).

fn main() -> std::process::ExitCode {
    surfkit::cli::main()
}
