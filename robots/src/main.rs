//! `robid`: robot dynamic model identification from the command line.

mod cli;

/// mimalloc keeps the memory it frees for the next allocation, where glibc's allocator
/// gives large blocks back to the system and faults them in again, zeroed: an
/// identification allocates each window's columns and each block's buffers anew, which
/// cost the hour of docs/performance.md#streaming-identification 7 % of its time.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    cli::run()
}
