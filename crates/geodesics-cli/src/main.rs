//! The `geodesics` command-line tool.
fn main() {}
