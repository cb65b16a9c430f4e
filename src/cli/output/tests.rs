use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use super::*;

/// A fresh folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("muse-output-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The id of a process that has ended (and been reaped).
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    assert_eq!(running(pid), Some(false), "pid {pid} still in /proc");
    pid
}

#[test]
fn run_files_and_the_temporary_names_of_earlier_versions() {
    for name in [
        "plans.jsonl",
        "view.html",
        "shard.json",
        "plans.partial",
        "bench.partial",
    ] {
        assert!(is_run_file(OsStr::new(name)), "{name}");
    }
    for name in [
        "notes.txt",
        "plans.json",
        "partial",
        ".plans.jsonl",
        "plans.jsonl.partial",
    ] {
        assert!(!is_run_file(OsStr::new(name)), "{name}");
    }
}

#[test]
fn temporary_names_are_told_apart() {
    let mine = temp_name(OsStr::new("view.html"), PARTIAL);
    assert_eq!(
        temp_of(&mine),
        Some(("view.html", PARTIAL, std::process::id()))
    );
    assert_eq!(temp_of(OsStr::new(".out.old-17")), Some(("out", OLD, 17)));
    assert_eq!(
        parse_temp(OsStr::new(".out.partial-17"), OsStr::new("out")),
        Some((PARTIAL, 17))
    );
    assert_eq!(
        parse_temp(OsStr::new(".out.partial-17"), OsStr::new("o")),
        None
    );
    for not in [
        "out.partial-17",
        ".out.partial-",
        ".out.partial-1x",
        ".out.other-17",
        "..partial-17",
        ".out.partial",
    ] {
        assert_eq!(temp_of(OsStr::new(not)), None, "{not}");
    }
}

#[test]
fn a_file_is_replaced_whole_and_a_link_never() {
    let dir = scratch("file");
    let path = dir.join("a.csv");
    write_atomically(&path, "one").unwrap();
    write_atomically(&path, "two").unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "two");
    assert_eq!(names(&dir), ["a.csv"], "no temporary file left");
    // A link is refused, and neither it nor what it points to changes.
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink(&path, &link).unwrap();
    let e = write_atomically(&link, "three").unwrap_err().to_string();
    assert!(e.contains("is a symbolic link"), "{e}");
    assert!(link.symlink_metadata().unwrap().is_symlink());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "two");
    // So is a folder, and nothing is left beside it.
    std::fs::create_dir(dir.join("sub")).unwrap();
    let e = write_atomically(&dir.join("sub"), "x")
        .unwrap_err()
        .to_string();
    assert!(e.contains("is a folder"), "{e}");
    assert_eq!(names(&dir), ["a.csv", "link.csv", "sub"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn file_outputs_are_checked_before_the_run() {
    let dir = scratch("checks");
    let input = dir.join("in.csv");
    std::fs::write(&input, "x").unwrap();
    let inputs = Inputs::new().add("--requests", &input);
    let err = |p: &Path| file("--out", p, &inputs).unwrap_err().to_string();
    assert!(err(&input).contains("is the input --requests"));
    // A hard link to the input is the input too.
    std::fs::hard_link(&input, dir.join("hard.csv")).unwrap();
    assert!(err(&dir.join("hard.csv")).contains("is the input --requests"));
    assert!(err(&dir.join("none/x.csv")).contains("its folder"));
    assert!(err(Path::new("/")).contains("give a file path"));
    let folder_path = format!("{}/", dir.join("none").display());
    assert!(err(Path::new(&folder_path)).contains("ends with /, a folder's path"));
    assert!(err(Path::new("/dev/null")).contains("is a character device"));
    assert!(file("--out", Path::new("-"), &inputs).unwrap().is_stdout());
    let a = file("--out", &dir.join("o.csv"), &inputs).unwrap();
    let b = file("--zones-out", &dir.join("./o.csv"), &inputs).unwrap();
    let c = file("--zones-out", &dir.join("p.csv"), &inputs).unwrap();
    let e = distinct(&[&a, &b]).unwrap_err().to_string();
    assert!(e.contains("--out and --zones-out both name"), "{e}");
    distinct(&[&a, &c]).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_folder_is_replaced_whole_and_its_folders_kept() {
    let dir = scratch("folder");
    let out = dir.join("out");
    let first = folder("--out", &out, &Inputs::new()).unwrap();
    assert!(!out.exists(), "written beside, not in place");
    for f in ["plans.jsonl", "summary.json", "view.html"] {
        std::fs::write(first.path().join(f), "1").unwrap();
    }
    first.commit().unwrap();
    std::fs::create_dir(out.join("sweep")).unwrap();
    std::fs::write(out.join("sweep/sweep.csv"), "kept").unwrap();
    let second = folder("--out", &out, &Inputs::new()).unwrap();
    std::fs::write(second.path().join("plans.jsonl"), "2").unwrap();
    assert_eq!(
        names(&out),
        ["plans.jsonl", "summary.json", "sweep", "view.html"]
    );
    second.commit().unwrap();
    assert_eq!(
        names(&out),
        ["plans.jsonl", "sweep"],
        "no file of the first run"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("plans.jsonl")).unwrap(),
        "2"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("sweep/sweep.csv")).unwrap(),
        "kept"
    );
    assert_eq!(names(&dir), ["out"], "nothing left beside it");
    // A run that fails leaves nothing; the folder is as it was.
    let failed = folder("--out", &out, &Inputs::new()).unwrap();
    std::fs::write(failed.path().join("plans.jsonl"), "3").unwrap();
    drop(failed);
    assert_eq!(names(&dir), ["out"]);
    assert_eq!(
        std::fs::read_to_string(out.join("plans.jsonl")).unwrap(),
        "2"
    );
    // A file no run writes is refused, at the start and at the commit.
    let late = folder("--out", &out, &Inputs::new()).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let e = folder("--out", &out, &Inputs::new())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("holds notes.txt (a regular file), which no muse run writes"),
        "{e}"
    );
    let e = late.commit().unwrap_err().to_string();
    assert!(e.contains("holds notes.txt"), "{e}");
    assert_eq!(names(&dir), ["out"]);
    // So is an input in it, and a file muse does not know of in the written folder.
    let e = folder(
        "--out",
        &out,
        &Inputs::new().add("--requests", &out.join("plans.jsonl")),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("holds the input --requests"), "{e}");
    std::fs::remove_file(out.join("notes.txt")).unwrap();
    let odd = folder("--out", &out, &Inputs::new()).unwrap();
    std::fs::write(odd.path().join("odd.txt"), "").unwrap();
    let e = odd.commit().unwrap_err().to_string();
    assert!(e.contains("odd.txt is not among the files"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn what_a_killed_run_left_is_cleaned_up_or_put_back() {
    let dir = scratch("stale");
    let out = dir.join("out");
    let dead = dead_pid();
    let at = |tag: &str, pid: u32| dir.join(format!(".out.{tag}-{pid}"));
    // Killed while writing: removed; a file being written too.
    std::fs::create_dir(at(PARTIAL, dead)).unwrap();
    std::fs::write(at(PARTIAL, dead).join("plans.jsonl"), "").unwrap();
    // Killed between moving the earlier folder aside and putting the new one in: put back.
    std::fs::create_dir_all(at(OLD, dead).join("sweep")).unwrap();
    std::fs::write(at(OLD, dead).join("summary.json"), "earlier").unwrap();
    clean_stale(&dir, OsStr::new("out"), &out);
    assert_eq!(names(&out), ["summary.json", "sweep"]);
    assert_eq!(names(&dir), ["out"]);
    // Killed after the new one was put in: the earlier one's folders are moved in.
    std::fs::create_dir_all(at(OLD, dead).join("bench")).unwrap();
    std::fs::write(at(OLD, dead).join("plans.jsonl"), "earlier").unwrap();
    clean_stale(&dir, OsStr::new("out"), &out);
    assert_eq!(names(&out), ["bench", "summary.json", "sweep"]);
    assert_eq!(names(&dir), ["out"]);
    // A running run's entries stay; a file being written by a killed run does not.
    let mine = folder("--out", &out, &Inputs::new()).unwrap();
    std::fs::write(at(PARTIAL, dead), "half").unwrap();
    clean_stale(&dir, OsStr::new("out"), &out);
    assert!(mine.path().is_dir());
    drop(mine);
    assert_eq!(names(&dir), ["out"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
