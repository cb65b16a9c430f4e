//! `muse airspace build`: the embedded Singapore files regenerated from `data/` (or checked), and
//! the airspace of any set of pads (`--pads`), with the day it is planned on.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;
use muse_airspace::builder::{BuildError, BuildOptions, build_airspace};
use muse_airspace::plane::Plane;
use muse_formats::day::FileDay;
use muse_formats::exclusions::Exclusions;

use crate::cli::output;

const AIRSPACE_FILE: &str = "airspace.geojson";
const ZONES_FILE: &str = "cbd_zone.geojson";

/// `muse airspace build [--check]`: the Singapore files of `out` written from `data/`, or
/// compared with what `data/` builds.
pub(super) fn singapore(out: &Path, check: bool) -> anyhow::Result<ExitCode> {
    let targets = if check {
        Vec::new()
    } else {
        build_targets(out)?
    };
    let built = muse_scenario::build_singapore_77().context("building the Singapore airspace")?;
    let files = [
        (AIRSPACE_FILE, &built.airspace_geojson),
        (ZONES_FILE, &built.zones_geojson),
    ];
    if check {
        let mut same = true;
        for (name, text) in files {
            let path = out.join(name);
            let committed = std::fs::read_to_string(&path)
                .with_context(|| format!("reading {}", path.display()))?;
            if committed == *text {
                println!("{}: identical to the build", path.display());
            } else {
                println!("{}: DIFFERS from the build", path.display());
                same = false;
            }
        }
        return Ok(if same {
            ExitCode::SUCCESS
        } else {
            ExitCode::FAILURE
        });
    }
    for (target, (_, text)) in targets.iter().zip(files) {
        target.write(text)?;
        println!("wrote {target} ({} bytes)", text.len());
    }
    Ok(ExitCode::SUCCESS)
}

/// The day `muse airspace build --pads` writes into the airspace file: `date` (default the
/// default scenario's) in time zone `time_zone` or at offset `utc_offset`; none without either.
pub(super) fn pads_day(
    time_zone: Option<&str>,
    utc_offset: Option<&str>,
    date: Option<&str>,
) -> anyhow::Result<Option<FileDay>> {
    let default = muse_scenario::by_name(muse_scenario::SINGAPORE_77)?
        .date
        .to_string();
    FileDay::asked(time_zone, utc_offset, date, &default).map_err(|e| {
        let option = match e.field {
            "date" => "--date",
            "utc_offset" => "--utc-offset",
            _ => "--time-zone",
        };
        anyhow::anyhow!("{option}: {}", e.message)
    })
}

/// The two files `muse airspace build` writes into the folder `out`, checked before the
/// build: `out` must be a folder (made if missing), and each file a regular file or none.
fn build_targets(out: &Path) -> anyhow::Result<Vec<output::FileOut>> {
    let shown = out.display();
    if out.as_os_str() == output::STDOUT {
        anyhow::bail!(
            "--out -: muse airspace build writes two files into a folder, and standard output takes a single file; give a folder path"
        );
    }
    match std::fs::metadata(out) {
        Ok(m) if m.is_dir() => {}
        Ok(m) => anyhow::bail!(
            "--out {shown} is {}; give a folder path: muse airspace build writes \
             {AIRSPACE_FILE} and {ZONES_FILE} into it",
            output::kind(m.file_type())
        ),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::create_dir_all(out).with_context(|| format!("--out {shown}: creating it"))?;
        }
        Err(e) => anyhow::bail!("--out {shown}: {e}"),
    }
    [AIRSPACE_FILE, ZONES_FILE]
        .iter()
        .map(|name| output::file("--out", &out.join(name), &output::Inputs::new()))
        .collect()
}

/// `muse airspace build --pads`: the airspace of any set of pads
/// (docs/reference.md#airspace-from-pads).
pub(super) fn from_pads(
    pads: &Path,
    crs: Option<&str>,
    exclude: &[PathBuf],
    land: Option<&Path>,
    day: Option<&FileDay>,
    max_corridor_m: Option<f64>,
    out: Option<&Path>,
) -> anyhow::Result<ExitCode> {
    let Some(out) = out else {
        anyhow::bail!(
            "--pads needs --out FILE: the airspace GeoJSON to write (`-`: standard output)"
        );
    };
    let plane = match crs {
        Some(text) => Plane::parse(text).map_err(|e| anyhow::anyhow!("--crs: {e}"))?,
        None => Plane::Utm,
    };
    let inputs = output::Inputs::new()
        .add("--pads", pads)
        .add_all("--exclude", exclude);
    let inputs = match land {
        Some(path) => inputs.add("--land", path),
        None => inputs,
    };
    let target = output::file("--out", out, &inputs)?;
    let nodes = muse_formats::pads::read_pads_file(pads)?;
    let mut exclusions = Exclusions::read_files(exclude)?;
    let opts = BuildOptions {
        plane,
        max_edge_length_m: max_corridor_m,
        exclusions: std::mem::take(&mut exclusions.polygons),
        ..BuildOptions::default()
    };
    let airspace = match build_airspace(nodes, &opts) {
        Ok(a) => a,
        Err(BuildError::Excluded { id, polygon }) => {
            anyhow::bail!(exclusions.pad_inside(&pads.display().to_string(), &id, polygon));
        }
        Err(e) => {
            return Err(e).with_context(|| format!("building the airspace of {}", pads.display()));
        }
    };
    let outline = match land {
        Some(path) => muse_formats::exclusions::read_exclusions_file(path)?,
        None => Vec::new(),
    };
    let text = muse_formats::airspace_geojson::write_airspace_file(&airspace, &outline, day);
    target.write(&text)?;
    eprintln!(
        "built {} pads into {} corridors in {plane} ({} bytes to {target})",
        airspace.node_count(),
        airspace.edge_count(),
        text.len(),
    );
    match day {
        Some(d) => eprintln!(
            "its day: {} at {}{}",
            d.day.date,
            d.day.offset,
            d.time_zone
                .as_ref()
                .map(|z| format!(" ({z})"))
                .unwrap_or_default()
        ),
        None => eprintln!(
            "note: no --time-zone: its day is the default scenario's (Singapore's date and \
             offset, +08:00); --time-zone NAME gives the pads' own"
        ),
    }
    Ok(ExitCode::SUCCESS)
}
