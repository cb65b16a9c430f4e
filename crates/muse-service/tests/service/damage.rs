//! Damage between a crash and a restart (docs/service.md#damage-is-never-silent): one byte
//! flipped in the store's files as a crash left them. The service either refuses to start,
//! naming the damage, or starts with every acknowledged flight as it was answered; a
//! transaction torn by the crash before its answer is discarded without a word.
//!
//! A crash is taken as the files stand while the service runs, with no request in flight: what
//! the operating system holds for the files is what SIGKILL leaves. They are copied in the
//! order that keeps them consistent (the record of acknowledgments, the database, the WAL).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use rand::{RngExt as _, SeedableRng as _};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

use crate::api::{Service, flight, in_secs, temp_dir};

/// Flights answered before the crash.
const FLIGHTS: usize = 400;
/// Flights answered in quick succession at the end, after a pause that lets the WAL start
/// again: the last WAL generation holds these transactions (see `Store::tidy`).
const LAST: usize = 8;
const SEED: u64 = 0x38_0001;

/// The files a crash left, and the answers given before it.
struct Crashed {
    dir: PathBuf,
    acked: Vec<Value>,
}

impl Drop for Crashed {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// How a start on damaged files ended.
#[derive(Debug)]
enum Outcome {
    /// Refused, with this message.
    Refused(String),
    /// Started with every acknowledged flight as answered.
    Intact,
    /// Started, but an acknowledged flight is missing or changed.
    Lost(String),
}

fn copy_files(from: &Path, to: &Path, files: &[&str]) {
    std::fs::create_dir_all(to).unwrap();
    for f in files {
        if from.join(f).exists() {
            std::fs::copy(from.join(f), to.join(f)).unwrap();
        }
    }
}

/// Answers `FLIGHTS` requests (the last `LAST` after a pause), then takes the files as a
/// crash would leave them. With `busy`, two threads load the CPU meanwhile. Also returns the
/// files of a crash that tore the last transaction before its answer: the record and the
/// database as they were before it, the WAL as it is after it (to be cut inside it).
async fn crashed(name: &str, busy: bool) -> (Crashed, Crashed) {
    let stop = Arc::new(AtomicBool::new(false));
    let spinners: Vec<_> = (0..if busy { 2 } else { 0 })
        .map(|_| {
            let stop = Arc::clone(&stop);
            std::thread::spawn(move || {
                let mut x = 1u64;
                while !stop.load(Ordering::Relaxed) {
                    x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                }
                x
            })
        })
        .collect();
    let s = Service::open(temp_dir(name), Vec::new(), |_| {})
        .await
        .unwrap();
    let legs = [("A", "C"), ("C", "A"), ("A", "B"), ("B", "C")];
    let mut acked = Vec::new();
    let torn = temp_dir(&format!("{name}-torn"));
    for k in 0..FLIGHTS {
        if k == FLIGHTS - 1 {
            copy_files(s.folder(), &torn, &["ACKED", "muse.db"]);
        }
        if k == FLIGHTS - LAST {
            tokio::time::sleep(Duration::from_millis(700)).await;
        }
        let (from, to) = legs[k % legs.len()];
        let departure = in_secs(600 + 97 * k as i64);
        let (code, v) = s
            .post(None, &flight(&format!("f{k}"), from, to, &departure))
            .await;
        assert!(code == 200 || code == 201, "{v}");
        acked.push(v);
    }
    stop.store(true, Ordering::Relaxed);
    for t in spinners {
        t.join().unwrap();
    }
    let dir = temp_dir(&format!("{name}-crashed"));
    copy_files(s.folder(), &dir, &["ACKED", "muse.db", "muse.db-wal"]);
    copy_files(s.folder(), &torn, &["muse.db-wal"]);
    let torn = Crashed {
        dir: torn,
        acked: acked[..FLIGHTS - 1].to_vec(),
    };
    (Crashed { dir, acked }, torn)
}

/// Starts the service on a copy of `files` with `damage` done to it, and says how it went.
async fn start_on(c: &Crashed, name: &str, damage: impl FnOnce(&Path)) -> Outcome {
    let dir = temp_dir(name);
    copy_files(&c.dir, &dir, &["ACKED", "muse.db", "muse.db-wal"]);
    damage(&dir);
    let s = match Service::open(dir.clone(), Vec::new(), |_| {}).await {
        Ok(s) => s,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&dir);
            return Outcome::Refused(e.to_string());
        }
    };
    for want in &c.acked {
        let id = want["request"].as_str().unwrap();
        let (code, got) = s.get(&format!("/v1/flights/{id}"), None).await;
        if (code, &got) != (200, want) {
            return Outcome::Lost(format!("{id}: {code} {got}"));
        }
    }
    Outcome::Intact
}

fn flip(path: &Path, at: usize) {
    let mut bytes = std::fs::read(path).unwrap();
    bytes[at] ^= 0x5a;
    std::fs::write(path, bytes).unwrap();
}

/// The frames of the WAL's current generation (their offsets), grouped by transaction, the
/// commit frame last in each; and the frame size.
fn transactions(wal: &[u8]) -> (Vec<Vec<usize>>, usize) {
    let be32 = |at: usize| u32::from_be_bytes(wal[at..at + 4].try_into().unwrap());
    let frame = 24 + be32(8) as usize;
    let salts = &wal[16..24];
    let (mut out, mut open) = (Vec::new(), Vec::new());
    let mut at = 32;
    while at + frame <= wal.len() && &wal[at + 8..at + 16] == salts {
        open.push(at);
        if be32(at + 4) != 0 {
            out.push(std::mem::take(&mut open));
        }
        at += frame;
    }
    (out, frame)
}

fn assert_refused_or_intact(outcome: &Outcome, what: &str) {
    match outcome {
        Outcome::Refused(m) => assert!(m.contains("is damaged"), "{what}: {m}"),
        Outcome::Intact => {}
        Outcome::Lost(m) => panic!("{what}: an acknowledged flight was lost: {m}"),
    }
}

/// The four places where one flipped byte lost acknowledged flights, and a tail torn before
/// its answer.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flip_in_acknowledged_frames_is_refused_and_a_torn_tail_is_not() {
    let (c, torn) = crashed("wal-places", false).await;
    let wal = std::fs::read(c.dir.join("muse.db-wal")).unwrap();
    let (txs, frame) = transactions(&wal);
    assert!(
        txs.len() >= 3 && txs.last().unwrap().len() >= 2,
        "the last WAL generation holds {} transactions",
        txs.len()
    );
    let last = txs.last().unwrap();
    let before = &txs[txs.len() - 2];
    let middle = txs[txs.len() / 2][0];
    let places = [
        (
            "the last transaction's commit frame",
            last[last.len() - 1] + 24 + 100,
        ),
        ("another frame of the last transaction", last[0] + 24 + 100),
        (
            "the commit frame of the transaction before",
            before[before.len() - 1] + 24 + 100,
        ),
        ("a salt in a frame header mid-WAL", middle + 9),
    ];
    for (k, (what, at)) in places.into_iter().enumerate() {
        let o = start_on(&c, &format!("wal-place-{k}"), |d| {
            flip(&d.join("muse.db-wal"), at);
        })
        .await;
        match &o {
            Outcome::Refused(m) => assert!(
                m.contains("is damaged") && m.contains("acknowledged") && m.contains("WAL"),
                "{what}: {m}"
            ),
            other => panic!("{what}: {other:?}"),
        }
    }
    // A tail torn by the crash before its answer: the WAL ends inside the last transaction,
    // the record of acknowledgments and the database are as they were before it.
    let cut = last[0] + frame * (last.len() / 2) + frame / 2;
    let o = start_on(&torn, "wal-torn", |d| {
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(d.join("muse.db-wal"))
            .unwrap();
        f.set_len(cut as u64).unwrap();
    })
    .await;
    assert!(matches!(o, Outcome::Intact), "a torn tail: {o:?}");
    // The database gone, its record of acknowledgments left: refused, never started empty.
    let o = start_on(&c, "wal-db-gone", |d| {
        std::fs::remove_file(d.join("muse.db")).unwrap();
        std::fs::remove_file(d.join("muse.db-wal")).unwrap();
    })
    .await;
    match &o {
        Outcome::Refused(m) => assert!(
            m.contains("is damaged: it is missing") && m.contains("ACKED"),
            "{m}"
        ),
        other => panic!("the database gone: {other:?}"),
    }
}

/// Random single-byte flips anywhere in the WAL and the database, on files a crash left with
/// the CPU quiet and with it loaded: never an acknowledged flight lost without a word. 100
/// flips a round; `MUSE_DAMAGE_FLIPS=N` asks for N.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn random_flips_are_refused_or_harmless() {
    let flips: usize = std::env::var("MUSE_DAMAGE_FLIPS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(100);
    println!("seed {SEED:#x}, {flips} flips a round");
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let (mut refused, mut intact) = (0, 0);
    for (round, busy) in [(0, false), (1, true)] {
        let (c, _) = crashed(&format!("flips-{round}"), busy).await;
        let sizes = ["muse.db", "muse.db-wal"]
            .map(|f| std::fs::metadata(c.dir.join(f)).map_or(0, |m| m.len() as usize));
        for k in 0..flips {
            let r = rng.random_range(0..sizes[0] + sizes[1]);
            let (file, at) = if r < sizes[0] {
                ("muse.db", r)
            } else {
                ("muse.db-wal", r - sizes[0])
            };
            let o = start_on(&c, &format!("flip-{round}-{k}"), |d| {
                flip(&d.join(file), at);
            })
            .await;
            assert_refused_or_intact(&o, &format!("{file} byte {at} (round {round}, flip {k})"));
            match o {
                Outcome::Refused(_) => refused += 1,
                _ => intact += 1,
            }
        }
    }
    println!("{refused} refused naming the damage, {intact} started intact");
}
