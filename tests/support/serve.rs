//! Running the real `muse serve` binary: starting it on an ephemeral loopback port and killing
//! it with SIGKILL (never a clean shutdown); and the scratch folders of every test.

use std::io::{BufRead as _, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// A running `muse serve`.
pub struct Server {
    /// The process.
    pub child: Child,
    /// Its base URL, e.g. `http://127.0.0.1:41234`.
    pub base: String,
}

impl Server {
    /// Kills the process with SIGKILL and reaps it.
    pub fn kill(mut self) {
        self.child.kill().expect("SIGKILL");
        self.child.wait().expect("reaped");
    }
}

impl Drop for Server {
    /// A test that fails still leaves no server behind (SIGKILL; an error means it is gone).
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `muse serve --listen 127.0.0.1:0 --data DATA` with `extra` arguments and waits for
/// the address it prints.
pub fn start(data: &Path, extra: &[&str]) -> Server {
    let data = data.display().to_string();
    start_with(&[extra, &["--data", &data]].concat())
}

/// Starts `muse serve --listen 127.0.0.1:0` with `args` (which say where its store is) and
/// waits for the address it prints.
pub fn start_with(args: &[&str]) -> Server {
    let mut child = Command::new(env!("CARGO_BIN_EXE_muse"))
        .args(["serve", "--listen", "127.0.0.1:0"])
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("muse serve starts");
    let stdout = child.stdout.take().expect("piped stdout");
    let mut lines = BufReader::new(stdout).lines();
    let base = loop {
        let line = lines
            .next()
            .expect("muse serve prints its address")
            .expect("readable stdout");
        if let Some(addr) = line.strip_prefix("listening on ") {
            break addr.trim().to_owned();
        }
    };
    // Keep draining stdout so the server never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines {});
    Server { child, base }
}

/// A folder under the target directory for one test, removed if it exists.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}
