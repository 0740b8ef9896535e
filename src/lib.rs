//! The sward application, built on the `sward` library (crates/sward): the window with its
//! panel, the AGC wind editor, the replay of recorded input and the frame budget
//! ([`app`]), the benchmarks ([`bench`]) and what the binary sets up before it starts
//! ([`runtime_env`]). The command line itself is `src/main.rs`.

pub mod app;
pub mod bench;
pub mod runtime_env;
