//! The `tetra` reference scene (docs/scenes.md) through the safe API.
//!
//!     cargo run --example tetra -- [N] [TICKS] [THREADS] [SEED]
//!
//! Defaults: N = 20000 tetrahedra, 3 ticks, all cores, seed 1. Detects at the
//! initial poses (tick 0), then steps TICKS times (motion with reflection at
//! the cube's walls), printing the pair count per tick and the first pairs.

use std::process::ExitCode;
use std::time::Instant;

use hgcd::scene::TetraDesc;
use hgcd::World;

fn arg<T: std::str::FromStr>(args: &[String], i: usize, default: T) -> Result<T, String> {
    match args.get(i) {
        None => Ok(default),
        Some(s) => s
            .parse()
            .map_err(|_| format!("argument {i}: cannot parse {s:?}")),
    }
}

fn print_tick(label: &str, world: &World) {
    let pairs = world.pairs();
    let stats = world.stats();
    let first: Vec<String> = pairs
        .iter()
        .take(5)
        .map(|p| format!("({}, {})", p.a.index(), p.b.index()))
        .collect();
    println!(
        "{label:<7} pairs {:>7} (containment {:>4})  candidates {:>8}  {:>7.1} ms  first: {}{}",
        pairs.len(),
        stats.containment_pairs,
        stats.candidate_pairs,
        1e3 * stats.total_seconds,
        first.join(" "),
        if pairs.len() > first.len() {
            " ..."
        } else {
            ""
        }
    );
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "-h" || a == "--help") {
        println!("usage: tetra [N=20000] [TICKS=3] [THREADS=0 (all cores)] [SEED=1]");
        return Ok(());
    }
    let n: u64 = arg(&args, 0, 20000)?;
    let ticks: u32 = arg(&args, 1, 3)?;
    let threads: u32 = arg(&args, 2, 0)?;
    let seed: u64 = arg(&args, 3, 1)?;
    println!(
        "hgcd {} (Rust bindings): scene tetra, n = {n}, seed = {seed}, {ticks} ticks, threads = {threads}",
        hgcd::version_string()
    );

    let t = Instant::now();
    let desc = TetraDesc::new(n, seed);
    let scene = desc.generate()?;
    let mut world = World::new(&desc.world_desc(threads))?;
    scene.populate(&mut world)?;
    println!(
        "scene generated and {} bodies created in {:.2} s",
        world.body_count(),
        t.elapsed().as_secs_f64()
    );

    world.detect()?;
    print_tick("tick 0", &world);
    for k in 1..=ticks {
        world.step()?;
        print_tick(&format!("tick {k}"), &world);
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tetra: {e}");
            ExitCode::FAILURE
        }
    }
}
