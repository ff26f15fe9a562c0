//! `cargo xtask fuzz` and the CI fuzz smoke run.

use crate::ctx::Ctx;
use crate::install::FUZZ_TOOLCHAIN;
use crate::process::{capture, run, show};
use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, ExitCode};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Seconds each fuzz target runs in `cargo xtask ci` (the smoke run).
pub(crate) const FUZZ_SMOKE_SECONDS: u64 = 15;
/// libFuzzer's `-seed` in the smoke run: a gate must not pass or fail by chance, so CI replays
/// one fixed sequence of mutations (a slower machine runs a prefix of it). Long runs (`cargo
/// xtask fuzz`) draw a new seed each time; what they find becomes a committed seed.
pub(crate) const FUZZ_SMOKE_SEED: u64 = 20_261_128;

/// `cargo xtask fuzz [--seconds N] [--target NAME]`.
pub(crate) fn fuzz_command(ctx: &Ctx, args: &[String]) -> ExitCode {
    let mut seconds = 600u64;
    let mut target = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match (a.as_str(), it.next()) {
            ("--seconds", Some(v)) => match v.parse() {
                Ok(n) => seconds = n,
                Err(_) => {
                    eprintln!("xtask: --seconds takes a whole number");
                    return ExitCode::from(2);
                }
            },
            ("--target", Some(v)) => target = Some(v.clone()),
            _ => {
                eprintln!("xtask: usage: cargo xtask fuzz [--seconds N] [--target NAME]");
                return ExitCode::from(2);
            }
        }
    }
    if fuzz(ctx, seconds, target.as_deref(), None) {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Builds the fuzz targets with cargo-fuzz on nightly and runs each (or `only`) for `seconds`,
/// starting from the committed seeds, with libFuzzer's `seed` when given; `true` when nothing
/// crashed.
pub(crate) fn fuzz(ctx: &Ctx, seconds: u64, only: Option<&str>, seed: Option<u64>) -> bool {
    let dir = ctx.root.join("fuzz");
    let fuzz_cmd = |args: &[&str]| {
        let mut c = Command::new("cargo");
        c.arg(format!("+{FUZZ_TOOLCHAIN}"))
            .arg("fuzz")
            .args(args)
            .current_dir(&dir)
            .env_remove("RUSTUP_TOOLCHAIN")
            .env_remove("CARGO");
        c
    };
    if !run(&mut fuzz_cmd(&["build", "-O"])) {
        return false;
    }
    let (ok, list, _) = capture(&mut fuzz_cmd(&["list"]));
    if !ok {
        return false;
    }
    let targets: Vec<&str> = list
        .lines()
        .map(str::trim)
        .filter(|t| !t.is_empty() && only.is_none_or(|o| o == *t))
        .collect();
    if targets.is_empty() {
        println!("xtask: no fuzz target matches");
        return false;
    }
    // Each fuzzer is single-threaded: run one per core, results printed in target order.
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<(bool, String)>>> = Mutex::new(vec![None; targets.len()]);
    std::thread::scope(|scope| {
        for _ in 0..workers.min(targets.len()) {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(t) = targets.get(k) else { break };
                let r = run_target(&dir, &fuzz_cmd, t, (seconds, seed));
                let mut all = results.lock().unwrap_or_else(|e| e.into_inner());
                if let Some(slot) = all.get_mut(k) {
                    *slot = Some(r);
                }
            });
        }
    });
    let mut all_ok = true;
    let mut summary = String::new();
    for (t, r) in targets
        .iter()
        .zip(results.into_inner().unwrap_or_else(|e| e.into_inner()))
    {
        let (ok, text) = r.unwrap_or((false, format!("fuzz {t}: did not run\n")));
        if !ok {
            print!("{text}");
        }
        let execs = text
            .lines()
            .find_map(|l| l.strip_prefix("stat::number_of_executed_units:"))
            .map_or("?".to_string(), |v| v.trim().to_string());
        let _ = writeln!(
            summary,
            "fuzz {t}: {} after {execs} executions in {seconds} s",
            if ok {
                "no findings"
            } else {
                "FAILED (see the output above)"
            }
        );
        all_ok &= ok;
    }
    print!("{summary}");
    all_ok
}

/// Runs one fuzz target for `seconds` from its corpus, seeds and dictionary: `(no crash,
/// the command line and its output)`.
fn run_target(
    dir: &Path,
    fuzz_cmd: &dyn Fn(&[&str]) -> Command,
    t: &str,
    (seconds, seed): (u64, Option<u64>),
) -> (bool, String) {
    let corpus = dir.join("corpus").join(t);
    let seeds = dir.join("seeds").join(t);
    let _ = std::fs::create_dir_all(&corpus);
    let mut args: Vec<String> = vec![
        "run".into(),
        "-O".into(),
        t.into(),
        corpus.display().to_string(),
    ];
    if seeds.is_dir() {
        args.push(seeds.display().to_string());
    }
    args.push("--".into());
    args.push(format!("-max_total_time={seconds}"));
    args.push("-print_final_stats=1".into());
    if let Some(seed) = seed {
        args.push(format!("-seed={seed}"));
    }
    let dict = dir.join("dicts").join(format!("{t}.dict"));
    if dict.is_file() {
        args.push(format!("-dict={}", dict.display()));
    }
    let argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut cmd = fuzz_cmd(&argv);
    let line = show(&cmd);
    println!("$ {line}");
    let (ok, stdout, stderr) = capture(&mut cmd);
    (ok, format!("$ {line}\n{stdout}{stderr}"))
}
