//! `muse export f3548`: each planned flight as an ASTM F3548-21 operational intent, and how
//! many pairs of flights intersect in 4-D at the chosen buffer.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{ArgMatches, Args};
use muse_export::f3548::{
    self, F3548Error, Flight, IntentEntry, MAX_BUFFER_M, MIN_VERTICAL_BUFFER_M, Options, intersect,
};
use muse_model::Instant;

use crate::cli::output;
use crate::cli::plans_run::RunArgs;
use crate::cli::ranges::in_range;

/// `--buffer-m`: from 0 to 1 km.
fn buffer_m(text: &str) -> Result<f64, String> {
    in_range(text, 0.0, MAX_BUFFER_M, "a number of metres")
}

/// `--vertical-buffer-m`: from 1 cm to 1 km.
fn vertical_buffer_m(text: &str) -> Result<f64, String> {
    in_range(
        text,
        MIN_VERTICAL_BUFFER_M,
        MAX_BUFFER_M,
        "a number of metres",
    )
}

/// Arguments of `muse export f3548`.
#[derive(Debug, Args)]
pub struct F3548Args {
    // Boxed: the run's options are large, and `muse export`'s formats share one enum.
    #[command(flatten)]
    run: Box<RunArgs>,
    /// Horizontal buffer B, metres, from 0 to 1000: each stay is a circle of radius B around
    /// its node, each corridor traversal the corridor widened by B on every side (0 is
    /// written as 1 cm, the standard's intersection precision).
    #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = buffer_m)]
    buffer_m: f64,
    /// Vertical buffer below and above each layer's altitude, metres, from 0.01 to 1000
    /// (default 3: layers 9.144 m apart stay apart).
    #[arg(long, value_name = "M", default_value_t = 3.0, allow_negative_numbers = true, value_parser = vertical_buffer_m)]
    vertical_buffer_m: f64,
    /// The managing USS's client id, written as each intent's `manager`.
    #[arg(long, value_name = "ID", default_value = "muse")]
    manager: String,
    /// The managing USS's base URL (`http(s)://…`, no trailing `/`), written as each
    /// intent's `uss_base_url`.
    #[arg(long, value_name = "URL", default_value = "https://uss.example.com")]
    uss_base_url: String,
    /// When the intents are to be shared (RFC 3339): each must then end after it and start
    /// within the standard's 30-day planning horizon. Default: not checked.
    #[arg(long, value_name = "TIME")]
    shared_at: Option<String>,
    /// Output file (`-`: standard output).
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
}

/// What the file is.
const FORMAT: &str =
    "ASTM F3548-21 operational intents (UTM API 1.0.0), written by muse export f3548";

/// The file's text: one JSON object, its header on the first line and each flight's entry on
/// a line of its own (compact, yet a day's file diffs and greps by flight).
fn file_text(args: &F3548Args, intents: &[IntentEntry]) -> anyhow::Result<String> {
    let header = serde_json::json!({
        "format": FORMAT,
        "buffer_m": args.buffer_m,
        "vertical_buffer_m": args.vertical_buffer_m,
    });
    let header = serde_json::to_string(&header).context("writing the intents")?;
    let mut text = String::with_capacity(intents.len() * 4_096 + header.len() + 32);
    // `{"buffer_m":…,"format":…,"vertical_buffer_m":…` then the list.
    text.push_str(header.trim_end_matches('}'));
    text.push_str(",\"operational_intents\":[");
    for (i, entry) in intents.iter().enumerate() {
        text.push_str(if i == 0 { "\n" } else { ",\n" });
        text.push_str(&serde_json::to_string(entry).context("writing the intents")?);
    }
    text.push_str("\n]}\n");
    Ok(text)
}

/// Runs `muse export f3548`.
pub fn run(args: &F3548Args, matches: &ArgMatches) -> anyhow::Result<ExitCode> {
    let files = args.run.files()?;
    let out = output::file("--out", &args.out, &files.inputs())?;
    let shared_at = args
        .shared_at
        .as_deref()
        .map(|t| Instant::parse_rfc3339(t).with_context(|| format!("--shared-at {t}")))
        .transpose()?;
    let options = Options {
        buffer_m: args.buffer_m,
        vertical_buffer_m: args.vertical_buffer_m,
        manager: args.manager.clone(),
        uss_base_url: args.uss_base_url.clone(),
        shared_at,
    };
    options.validate().map_err(|e| {
        let option = match e {
            F3548Error::Buffer(_) => "--buffer-m",
            F3548Error::VerticalBuffer(_) => "--vertical-buffer-m",
            F3548Error::BaseUrl(_) => "--uss-base-url",
            _ => "--manager",
        };
        anyhow::anyhow!("{option}: {e}")
    })?;
    let run = files.open(matches)?;
    let requests = run.entries.len();
    let flights: Vec<Flight<'_>> = run
        .flown()
        .map(|(request, plan)| Flight { request, plan })
        .collect();
    let intents =
        f3548::operational_intents(&run.world.airspace, &flights, &options).map_err(|e| {
            let option = if matches!(e, F3548Error::Horizon { .. }) {
                " (--shared-at)"
            } else {
                ""
            };
            anyhow::anyhow!(
                "{}: exporting its flights{option}: {e}",
                run.plans.display()
            )
        })?;
    let ois: Vec<_> = intents
        .iter()
        .map(|e| e.operational_intent.clone())
        .collect();
    let pairs = intersect::intersecting_pairs(&ois).context("comparing the intents")?;
    let text = file_text(args, &intents)?;
    out.write(&text)?;
    output::say(
        out.is_stdout(),
        format_args!(
            "wrote {out}: {} operational intents ({} volumes) of {requests} requests; \
             {} of {} flights' pairs intersect in 4-D at buffer {} m",
            pairs.intents, pairs.volumes, pairs.intersecting, pairs.pairs, args.buffer_m
        ),
    );
    Ok(ExitCode::SUCCESS)
}
