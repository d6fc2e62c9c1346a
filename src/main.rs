//! The smoothlab command line: argument parsing and printing only.

fn main() {}
