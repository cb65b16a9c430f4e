//! A throwaway PostgreSQL for the tests (issue 40): Debian's `postgresql` binaries, a cluster
//! made by `initdb` in a fresh folder under the system's temporary folder, run by an
//! unprivileged user (`postgres` when the tests run as root: PostgreSQL refuses root), on
//! an ephemeral loopback port, and stopped (`pg_ctl stop -m immediate`, the process this
//! harness started and no other) and removed when dropped.
//!
//! [`Throwaway::shared`] is one cluster for the whole test process, each test on a database of
//! its own ([`Throwaway::database`]); a watchdog stops and removes it once the process is gone.
//!
//! Where PostgreSQL is not installed the tests that need it say so and pass, except under CI
//! (`CI` set), where `.ci/run` installs it and its absence is a failure.

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

/// A running throwaway cluster with one database, `muse`, owned by the role `muse`.
#[derive(Debug)]
pub struct Throwaway {
    bin: PathBuf,
    dir: PathBuf,
    port: u16,
    /// The user its programs run as (`None`: the tests' own).
    user: Option<String>,
}

/// How many clusters this process has made (each gets its own folder).
static MADE: AtomicU32 = AtomicU32::new(0);

/// The cluster the test process shares (`None`: PostgreSQL is not installed).
static SHARED: OnceLock<Option<Throwaway>> = OnceLock::new();

impl Throwaway {
    /// Starts one, or says why it cannot (`None`; a panic under CI).
    pub fn start() -> Option<Throwaway> {
        let Some(bin) = binaries() else {
            assert!(
                std::env::var_os("CI").is_none(),
                "PostgreSQL is not installed (initdb not found), and CI needs it"
            );
            eprintln!("PostgreSQL is not installed (apt-get install postgresql): skipped");
            return None;
        };
        let dir = std::env::temp_dir().join(format!(
            "muse-pg-{}-{}",
            std::process::id(),
            MADE.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a folder for the cluster");
        let user = running_as_root().then(|| "postgres".to_owned());
        if let Some(u) = &user {
            let (uid, gid) =
                ids_of(u).expect("the postgres user exists where PostgreSQL is installed");
            std::os::unix::fs::chown(&dir, Some(uid), Some(gid))
                .expect("the folder given to postgres");
        }
        let mut pg = Throwaway {
            bin,
            dir,
            port: 0,
            user,
        };
        let data = pg.data();
        pg.run(
            "initdb",
            &[
                "-D",
                &data,
                "-U",
                "muse",
                "--auth=trust",
                "-E",
                "UTF8",
                "--locale=C",
                "--no-sync",
            ],
        );
        // An ephemeral port: the first free one the system gives, tried until one is taken.
        for _ in 0..5 {
            pg.port = free_port();
            if pg.try_start() {
                pg.run(
                    "createdb",
                    &[
                        "-h",
                        "127.0.0.1",
                        "-p",
                        &pg.port.to_string(),
                        "-U",
                        "muse",
                        "muse",
                    ],
                );
                return Some(pg);
            }
        }
        panic!("PostgreSQL would not start: {}", pg.log());
    }

    /// One cluster for the whole test process, started by the first test that asks (`None`
    /// where PostgreSQL is not installed, saying so; a panic under CI). A static is never
    /// dropped, so a watchdog process stops the cluster and removes its folder once this
    /// process has ended, however it ended: it checks twice a second, and stops by itself.
    pub fn shared() -> Option<&'static Throwaway> {
        SHARED
            .get_or_init(|| {
                let pg = Throwaway::start()?;
                let stop = format!(
                    "{} {}",
                    pg.as_user(&pg.bin.join("pg_ctl").display().to_string()),
                    format_args!("-D '{}' -m immediate -w stop", pg.data())
                );
                let script = format!(
                    "while kill -0 {pid} 2>/dev/null; do sleep 0.5; done; {stop} >/dev/null 2>&1; \
                     rm -rf '{dir}'",
                    pid = std::process::id(),
                    dir = pg.dir.display()
                );
                // Started in the background by a shell that ends at once (and is waited for).
                let started = Command::new("sh")
                    .args(["-c", &format!("( {script} ) </dev/null >/dev/null 2>&1 &")])
                    .status()
                    .expect("the cluster's watchdog starts");
                assert!(started.success(), "the cluster's watchdog starts");
                Some(pg)
            })
            .as_ref()
    }

    /// A new, empty database `name` (dropped first if it exists): its URL.
    pub fn database(&self, name: &str) -> String {
        let port = self.port.to_string();
        let common = ["-h", "127.0.0.1", "-p", &port, "-U", "muse"];
        let _ = self.command("dropdb", &[&common[..], &["--if-exists", name]].concat());
        self.run("createdb", &[&common[..], &[name]].concat());
        format!("postgres://muse@127.0.0.1:{}/{name}", self.port)
    }

    /// The command line that runs `program` as the cluster's user.
    fn as_user(&self, program: &str) -> String {
        match &self.user {
            Some(u) => format!("runuser -u {u} -- {program}"),
            None => program.to_owned(),
        }
    }

    /// The URL of its database.
    pub fn url(&self) -> String {
        format!("postgres://muse@127.0.0.1:{}/muse", self.port)
    }

    /// Stops it as a crash would (`-m immediate`: no checkpoint, the WAL replayed at the next
    /// start) and starts it again on the same port.
    pub fn crash_and_restart(&self) {
        self.stop();
        assert!(
            self.try_start(),
            "PostgreSQL would not start again: {}",
            self.log()
        );
    }

    fn data(&self) -> String {
        self.dir.join("data").display().to_string()
    }

    fn log(&self) -> String {
        std::fs::read_to_string(self.dir.join("log")).unwrap_or_default()
    }

    /// `pg_ctl start` on the port, waiting until it accepts connections.
    fn try_start(&self) -> bool {
        let options = format!(
            "-c listen_addresses=127.0.0.1 -c port={} -c unix_socket_directories={}",
            self.port,
            self.dir.display()
        );
        let log = self.dir.join("log").display().to_string();
        self.command(
            "pg_ctl",
            &[
                "-D",
                &self.data(),
                "-o",
                &options,
                "-l",
                &log,
                "-w",
                "start",
            ],
        )
        .status
        .success()
    }

    fn stop(&self) {
        let _ = self.command(
            "pg_ctl",
            &["-D", &self.data(), "-m", "immediate", "-w", "stop"],
        );
    }

    /// Runs one of its programs; panics with its output if it fails.
    fn run(&self, program: &str, args: &[&str]) {
        let o = self.command(program, args);
        assert!(
            o.status.success(),
            "{program} {args:?}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    }

    fn command(&self, program: &str, args: &[&str]) -> Output {
        let path = self.bin.join(program);
        let mut c = match &self.user {
            Some(u) => {
                let mut c = Command::new("runuser");
                c.args(["-u", u, "--"]).arg(&path);
                c
            }
            None => Command::new(&path),
        };
        c.args(args)
            .current_dir(&self.dir)
            .output()
            .expect("a PostgreSQL program runs")
    }
}

impl Drop for Throwaway {
    fn drop(&mut self) {
        self.stop();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Runs `statement` on the database at `url` (on a thread of its own: the client blocks, and
/// the tests run it from inside their runtime). Panics if it fails.
pub fn execute(url: &str, statement: &str) {
    let (url, statement) = (url.to_owned(), statement.to_owned());
    std::thread::spawn(move || {
        let mut client = postgres::Client::connect(&url, postgres::NoTls).expect("connects");
        client
            .batch_execute(&statement)
            .unwrap_or_else(|e| panic!("{statement}: {e}"));
    })
    .join()
    .expect("the statement runs");
}

/// The folder of PostgreSQL's programs: Debian's newest `/usr/lib/postgresql/N/bin`, else
/// where `initdb` is on the `PATH`.
fn binaries() -> Option<PathBuf> {
    let debian = std::fs::read_dir("/usr/lib/postgresql")
        .ok()
        .and_then(|entries| {
            entries
                .filter_map(Result::ok)
                .filter_map(|e| {
                    let version: u32 = e.file_name().to_str()?.parse().ok()?;
                    let bin = e.path().join("bin");
                    bin.join("initdb").exists().then_some((version, bin))
                })
                .max()
                .map(|(_, bin)| bin)
        });
    debian.or_else(|| {
        std::env::var_os("PATH").and_then(|paths| {
            std::env::split_paths(&paths).find(|p| Path::new(p).join("initdb").exists())
        })
    })
}

/// Whether the tests run as root (`id -u` says 0).
fn running_as_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// The user and group ids of `user`.
fn ids_of(user: &str) -> Option<(u32, u32)> {
    let id = |flag: &str| -> Option<u32> {
        let o = Command::new("id").args([flag, user]).output().ok()?;
        String::from_utf8_lossy(&o.stdout).trim().parse().ok()
    };
    Some((id("-u")?, id("-g")?))
}

/// A loopback port free now.
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free loopback port")
}

/// The harness itself: a cluster starts, takes a committed row, keeps it through a crash
/// (`-m immediate`) and restart, and is gone when dropped.
#[test]
fn a_throwaway_postgres_keeps_what_it_committed_through_a_crash() {
    let Some(pg) = Throwaway::start() else { return };
    let mut client = postgres::Client::connect(&pg.url(), postgres::NoTls).expect("connects");
    client
        .batch_execute("CREATE TABLE t (id bigint PRIMARY KEY, v text NOT NULL)")
        .unwrap();
    client
        .execute("INSERT INTO t VALUES ($1, $2)", &[&7_i64, &"seven"])
        .unwrap();
    drop(client);
    pg.crash_and_restart();
    let mut client = postgres::Client::connect(&pg.url(), postgres::NoTls).expect("connects again");
    let row = client
        .query_one("SELECT v FROM t WHERE id = $1", &[&7_i64])
        .unwrap();
    assert_eq!(row.get::<_, String>(0), "seven");
    drop(client);
    let dir = pg.dir.clone();
    drop(pg);
    assert!(!dir.exists(), "the cluster's folder is removed");
}
