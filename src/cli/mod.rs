//! Command implementations of the CLI; `main.rs` only parses arguments and dispatches here.
//! Each engine has its own module.

/// `println!` that ignores write errors, so that `plcsynth ... | head` ends quietly instead of
/// panicking on a closed pipe.
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

pub mod bench;
pub mod ltl;
pub mod sct;
pub mod timed;
