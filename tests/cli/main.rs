//! The command line, run as a user runs it: every subcommand on real and hostile inputs, its files,
//! messages and exit statuses.

mod bad_input;
#[path = "../common/mod.rs"]
mod common;
mod creases;
mod degenerate_facets;
mod eat;
mod eat_folder;
mod fair;
mod fair_g2;
mod hostile;
mod hostile_matrix;
mod html;
mod info_convert;
mod repair;
mod spline_memory;
mod text_summaries;
