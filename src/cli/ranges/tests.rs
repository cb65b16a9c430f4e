use clap::error::ErrorKind;
use clap::{ArgAction, Command, CommandFactory as _};

use super::*;

#[test]
fn parsers_refuse_what_lies_outside_with_the_range() {
    assert_eq!(max_flight_min("20"), Ok(20.0));
    assert_eq!(max_flight_min(" 1440 "), Ok(1_440.0));
    for bad in [
        "0", "0.5", "1441", "1e12", "-20", "NaN", "inf", "-inf", "", "twenty",
    ] {
        assert_eq!(
            max_flight_min(bad),
            Err("must be a number of minutes from 1 to 1440".to_owned()),
            "{bad}"
        );
    }
    assert_eq!(requests("10000000"), Ok(10_000_000));
    for bad in [
        "0",
        "10000001",
        "2000000000",
        "-1",
        "1e3",
        "1.5",
        "99999999999999999999999",
    ] {
        assert_eq!(
            requests(bad),
            Err("must be a whole number of requests from 1 to 10000000".to_owned()),
            "{bad}"
        );
    }
    assert_eq!(seed("18446744073709551615"), Ok(u64::MAX));
    assert!(
        seed("-1")
            .unwrap_err()
            .contains("from 0 to 18446744073709551615")
    );
    assert_eq!(rate_limit("0"), Ok(0.0));
    assert_eq!(separation_s("0"), Ok(0.0));
    assert!(speed_kmh("-30").unwrap_err().ends_with("from 1 to 1000"));
}

#[test]
fn timeouts_parse_and_are_bounded() {
    assert_eq!(http_timeout("10"), Ok(Duration::from_secs(10)));
    assert_eq!(http_timeout("2.5"), Ok(Duration::from_millis(2_500)));
    for bad in ["0", "-1", "NaN", "inf", "", "ten", "0.01", "1e9"] {
        let e = http_timeout(bad).unwrap_err();
        assert!(e.contains("seconds from 0.1 to 86400"), "{bad}: {e}");
    }
}

/// Every command, as the words that name it, with its definition.
fn commands(cmd: &Command, path: &[String], out: &mut Vec<(Vec<String>, Command)>) {
    for sub in cmd.get_subcommands() {
        let mut p = path.to_vec();
        p.push(sub.get_name().to_owned());
        out.push((p.clone(), sub.clone()));
        commands(sub, &p, out);
    }
}

/// The `X to Y` of a message saying `… from X to Y …`.
fn range_of(message: &str) -> Option<String> {
    let rest = &message[message.find(" from ")? + 6..];
    let mut words = rest.split_whitespace();
    let lo = words.next()?;
    (words.next()? == "to").then_some(())?;
    let hi = words.next()?.trim_end_matches([';', ',', '.', ')']);
    Some(format!("{lo} to {hi}"))
}

/// Options clap reads as something other than text that are not numbers.
const NOT_NUMBERS: [&str; 3] = ["listen", "store", "advertise"];

/// Every option of every command that takes a number: its errors for bad numbers state one
/// range, its `--help` states the same, and a negative number is read as its value (and
/// refused for being out of range), never as an unknown option. An option that refuses a
/// word without stating a range is a numeric option left without one: a failure.
#[test]
fn every_numeric_option_states_its_range_in_its_errors_and_help() {
    let mut all = Vec::new();
    commands(&crate::cli::Cli::command(), &[], &mut all);
    let mut ranged = 0;
    let mut problems = Vec::new();
    for (path, cmd) in &all {
        for arg in cmd.get_arguments() {
            let Some(long) = arg.get_long() else { continue };
            if NOT_NUMBERS.contains(&long) {
                continue;
            }
            if !matches!(arg.get_action(), ArgAction::Set | ArgAction::Append) {
                continue;
            }
            let attempt = |value: &str| {
                let mut argv = vec!["muse".to_owned()];
                argv.extend(path.iter().cloned());
                argv.extend([format!("--{long}"), value.to_owned()]);
                crate::cli::Cli::command().try_get_matches_from(argv)
            };
            let Err(word) = attempt("abc") else { continue };
            if word.kind() != ErrorKind::ValueValidation {
                continue; // a choice among names (clap lists them), or text read later
            }
            let name = format!("muse {} --{long}", path.join(" "));
            let message = word.to_string();
            let Some(range) = range_of(&message) else {
                problems.push(format!("{name}: refuses a word without a range: {message}"));
                continue;
            };
            ranged += 1;
            for bad in ["NaN", "inf", "-5", "1e30"] {
                match attempt(bad) {
                    Ok(_) => problems.push(format!("{name}: accepts {bad}")),
                    Err(e) if e.kind() != ErrorKind::ValueValidation => {
                        problems.push(format!("{name} {bad}: {e}"));
                    }
                    Err(e) if range_of(&e.to_string()).as_deref() != Some(&range) => {
                        problems.push(format!("{name} {bad}: another range: {e}"));
                    }
                    Err(_) => {}
                }
            }
            let help = format!(
                "{} {}",
                arg.get_help().map(ToString::to_string).unwrap_or_default(),
                arg.get_long_help()
                    .map(ToString::to_string)
                    .unwrap_or_default()
            );
            if !help.contains(&range) {
                problems.push(format!("{name}: --help does not say `{range}`: {help}"));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(ranged > 40, "only {ranged} numeric options found");
}
