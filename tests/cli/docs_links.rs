//! Every relative link of the documentation resolves: in `README.md`, every Markdown file under
//! `docs/` and every Markdown file they link to, each link or image `[text](target)` and each
//! `<img src="target">` whose target is not a URL (`http:`, `https:`, `mailto:`) must name a
//! file or folder that exists, relative to the linking file; a `#anchor`, alone or after a
//! Markdown file, must be the GitHub slug of a heading of that file. Links in fenced code blocks
//! and inline code spans are not links. Every broken link is named with its file and line.
//! The README stays a front door: at most [`README_MAX_LINES`] lines, citing no document outside
//! the repository ("SPEC").

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};

/// The README's length limit.
const README_MAX_LINES: usize = 250;

/// Where the checker reads files: the repository on disk, or files in memory (its own test).
trait Files {
    /// The text of the file at `path` (relative to the root), if it is a readable file.
    fn read(&self, path: &Path) -> Option<String>;
    /// Whether a file or folder exists at `path` (relative to the root).
    fn exists(&self, path: &Path) -> bool;
}

/// The repository on disk.
struct Disk(PathBuf);

impl Files for Disk {
    fn read(&self, path: &Path) -> Option<String> {
        std::fs::read_to_string(self.0.join(path)).ok()
    }
    fn exists(&self, path: &Path) -> bool {
        self.0.join(path).exists()
    }
}

/// Files in memory: path → text; a folder exists when some file is under it.
struct Memory(BTreeMap<PathBuf, String>);

impl Files for Memory {
    fn read(&self, path: &Path) -> Option<String> {
        self.0.get(path).cloned()
    }
    fn exists(&self, path: &Path) -> bool {
        self.0.keys().any(|p| p.starts_with(path))
    }
}

/// A link found in a Markdown file: its 1-based line and its target as written.
#[derive(Debug, PartialEq)]
struct Link {
    line: usize,
    target: String,
}

/// GitHub's anchor for a heading's text: lower case; every character but letters, digits
/// (any script), spaces, hyphens and underscores dropped; spaces turned into hyphens.
fn slug(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The text of a Markdown file with fenced code blocks and inline code spans blanked out
/// (replaced by spaces; line breaks kept, so line numbers stay right).
fn prose(text: &str) -> String {
    // Fenced blocks first, line by line: a fence opens with three or more backticks or
    // tildes and closes with at least as many of the same character.
    let mut out = String::with_capacity(text.len());
    let mut fence: Option<(char, usize)> = None;
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let run = |c: char| trimmed.chars().take_while(|&x| x == c).count();
        let opening = ['`', '~'].into_iter().find(|&c| run(c) >= 3);
        let blank = match (fence, opening) {
            (None, Some(c)) => {
                fence = Some((c, run(c)));
                true
            }
            (Some((c, n)), _) => {
                if run(c) >= n && trimmed.trim_start_matches(c).trim().is_empty() {
                    fence = None;
                }
                true
            }
            (None, None) => false,
        };
        if blank {
            out.extend(line.chars().map(|c| if c == '\n' { c } else { ' ' }));
        } else {
            out.push_str(line);
        }
    }
    // Then code spans: a run of N backticks up to the next run of exactly N, within one
    // paragraph (not across a blank line).
    let chars: Vec<char> = out.chars().collect();
    let mut blanked = chars.clone();
    let run_at = |i: usize| chars[i..].iter().take_while(|&&c| c == '`').count();
    // Whether the line after the line break at `j` is blank.
    let blank_line_after = |j: usize| {
        chars[j + 1..]
            .iter()
            .take_while(|&&c| c != '\n')
            .all(|c| c.is_whitespace())
    };
    let mut i = 0;
    while i < chars.len() {
        if chars[i] != '`' {
            i += 1;
            continue;
        }
        let n = run_at(i);
        let mut j = i + n;
        let mut close = None;
        while j < chars.len() {
            if chars[j] == '\n' && blank_line_after(j) {
                break;
            }
            if chars[j] == '`' {
                let m = run_at(j);
                if m == n {
                    close = Some(j);
                    break;
                }
                j += m;
            } else {
                j += 1;
            }
        }
        if let Some(j) = close {
            for c in &mut blanked[i..j + n] {
                if *c != '\n' {
                    *c = ' ';
                }
            }
            i = j + n;
        } else {
            i += n;
        }
    }
    blanked.into_iter().collect()
}

/// The links of a Markdown file: `[text](target)`, `![alt](target)` and `<img src="target">`
/// outside code.
fn links(text: &str) -> Vec<Link> {
    let mut found = Vec::new();
    for (index, line) in prose(text).lines().enumerate() {
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let target: String = after
                .chars()
                .take_while(|c| *c != ')' && !c.is_whitespace())
                .collect();
            if !target.is_empty() {
                found.push(Link {
                    line: index + 1,
                    target,
                });
            }
            rest = after;
        }
        let mut rest = line;
        while let Some(at) = rest.find("<img") {
            rest = &rest[at + 4..];
            let end = rest.find('>').unwrap_or(rest.len());
            let tag = &rest[..end];
            if let Some(src) = tag.find("src=") {
                let value = &tag[src + 4..];
                let quote = value.chars().next().filter(|c| matches!(c, '"' | '\''));
                let target: String = match quote {
                    Some(q) => value[1..].chars().take_while(|c| *c != q).collect(),
                    None => value.chars().take_while(|c| !c.is_whitespace()).collect(),
                };
                found.push(Link {
                    line: index + 1,
                    target,
                });
            }
        }
    }
    found
}

/// The anchors of a Markdown file's headings (ATX `#` headings outside code), as GitHub makes
/// them: the slug of the heading's text (a link's text in place of the link), the second and
/// later headings with the same slug suffixed `-1`, `-2`, …
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    let mut anchors = BTreeSet::new();
    let code_free = prose(text);
    for (line, original) in code_free.lines().zip(text.lines()) {
        let hashes = line.chars().take_while(|c| *c == '#').count();
        if !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        // The heading as written (code spans included), without closing hashes.
        let heading = original[hashes..].trim().trim_end_matches('#').trim_end();
        let base = slug(&link_texts(heading));
        let count = seen.entry(base.clone()).or_insert(0);
        anchors.insert(if *count == 0 {
            base.clone()
        } else {
            format!("{base}-{count}")
        });
        *count += 1;
    }
    anchors
}

/// `text` with each Markdown link `[label](target)` replaced by its label.
fn link_texts(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find("](") {
        let Some(close) = rest[at..].find(')') else {
            break;
        };
        out.push_str(&rest[..at].replacen('[', "", 1));
        rest = &rest[at + close + 1..];
    }
    out.push_str(rest);
    out
}

/// `path` with `.` and `..` resolved lexically; `None` if it climbs above the root.
fn normalise(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::Normal(name) => out.push(name),
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(out)
}

/// Every broken relative link of the Markdown files `start` and of every Markdown file they
/// link to, in turn, as `file:line: link (what is wrong)`.
fn broken_links(files: &dyn Files, start: &[PathBuf]) -> Vec<String> {
    let mut todo: Vec<PathBuf> = start.to_vec();
    let mut done = BTreeSet::new();
    let mut broken = Vec::new();
    let mut anchors_of: BTreeMap<PathBuf, Option<BTreeSet<String>>> = BTreeMap::new();
    while let Some(file) = todo.pop() {
        if !done.insert(file.clone()) {
            continue;
        }
        let Some(text) = files.read(&file) else {
            broken.push(format!("{}: cannot be read", file.display()));
            continue;
        };
        let dir = file.parent().unwrap_or(Path::new(""));
        for Link { line, target } in links(&text) {
            let scheme = ["http:", "https:", "mailto:"];
            if scheme.iter().any(|s| target.starts_with(s)) {
                continue;
            }
            let mut report = |what: &str| {
                broken.push(format!("{}:{line}: ({target}): {what}", file.display()));
            };
            let (path, anchor) = match target.split_once('#') {
                Some((path, anchor)) => (path, Some(anchor)),
                None => (target.as_str(), None),
            };
            let resolved = if path.is_empty() {
                Some(file.clone())
            } else {
                normalise(&dir.join(path))
            };
            let Some(resolved) = resolved else {
                report("points outside the repository");
                continue;
            };
            if !files.exists(&resolved) {
                report(&format!("{} does not exist", resolved.display()));
                continue;
            }
            let markdown = resolved.extension().is_some_and(|e| e == "md");
            if markdown && !done.contains(&resolved) {
                todo.push(resolved.clone());
            }
            let Some(anchor) = anchor else { continue };
            if !markdown {
                report("an anchor into a file that is not Markdown");
                continue;
            }
            let known = anchors_of
                .entry(resolved.clone())
                .or_insert_with(|| files.read(&resolved).map(|t| anchors(&t)));
            if !known.as_ref().is_some_and(|a| a.contains(anchor)) {
                report(&format!("{} has no heading #{anchor}", resolved.display()));
            }
        }
    }
    broken
}

/// `README.md` and every Markdown file under `docs/`, relative to the repository root.
fn documentation(root: &Path) -> Vec<PathBuf> {
    let mut found = vec![PathBuf::from("README.md")];
    let mut dirs = vec![PathBuf::from("docs")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(root.join(&dir)).unwrap() {
            let entry = entry.unwrap();
            let path = dir.join(entry.file_name());
            if entry.file_type().unwrap().is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_relative_link_of_the_readme_and_docs_resolves() {
    let start = documentation(&root());
    assert!(start.len() > 10, "too few Markdown files found: {start:?}");
    let broken = broken_links(&Disk(root()), &start);
    assert!(
        broken.is_empty(),
        "{} broken link(s) in the documentation:\n{}",
        broken.len(),
        broken.join("\n")
    );
}

#[test]
fn the_readme_is_a_front_door_citing_nothing_outside_the_repository() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, more than {README_MAX_LINES}: move the detail to docs/"
    );
    assert!(
        !readme.contains("SPEC"),
        "README.md cites SPEC, a document not in the repository"
    );
    for file in documentation(&root()) {
        let text = std::fs::read_to_string(root().join(&file)).unwrap();
        assert!(
            !text.contains("SPEC §"),
            "{} cites SPEC, a document not in the repository",
            file.display()
        );
    }
}

#[test]
fn slugs_are_githubs() {
    assert_eq!(slug("The store: `muse.db`"), "the-store-musedb");
    assert_eq!(
        slug("Results: the paper's experiment"),
        "results-the-papers-experiment"
    );
    assert_eq!(
        slug("Sharing flights with other USSs: ASTM F3548-21 operational intents"),
        "sharing-flights-with-other-usss-astm-f3548-21-operational-intents"
    );
    assert_eq!(slug("Zürich — große_Höhe 2"), "zürich--große_höhe-2");
    let text = "# Guide\n\n## Step\n\n```sh\n## not a heading\n```\n\n## Step\n\n### Step\n\n\
                ## [Linked](x.md) `code`\n";
    let expected = ["guide", "step", "step-1", "step-2", "linked-code"];
    assert_eq!(
        anchors(text),
        expected.iter().map(|s| (*s).to_owned()).collect()
    );
}

#[test]
fn the_checker_finds_every_broken_link_and_skips_code() {
    let files = Memory(
        [
            (
                "README.md",
                "# Title\n\n\
                 See [the guide](docs/guide.md), [its step](docs/guide.md#first-step) and \
                 [here](#title).\n\
                 ![map](docs/map.svg) <img src=\"docs/map.svg\" width=\"80\">\n\
                 A [missing file](docs/gone.md) and [a wrong anchor](docs/guide.md#no-such-step).\n\
                 [A site](https://example.org/x) and [mail](mailto:a@b.c) are not checked.\n\
                 `[in code](nowhere.md)` and ``a `[span](nowhere.md)` `` are not links.\n\
                 \n```md\n[in a fence](nowhere.md)\n```\n",
            ),
            (
                "docs/guide.md",
                "# Guide\n\n## First step\n\nBack to the [README](../README.md#title); \
                 [up too far](../../x.md); <img src='gone.png'>.\n",
            ),
            ("docs/map.svg", "<svg/>"),
        ]
        .into_iter()
        .map(|(p, t)| (PathBuf::from(p), t.to_owned()))
        .collect(),
    );
    let found = links(&files.read(Path::new("README.md")).unwrap());
    let targets: Vec<&str> = found.iter().map(|l| l.target.as_str()).collect();
    assert_eq!(
        targets,
        [
            "docs/guide.md",
            "docs/guide.md#first-step",
            "#title",
            "docs/map.svg",
            "docs/map.svg",
            "docs/gone.md",
            "docs/guide.md#no-such-step",
            "https://example.org/x",
            "mailto:a@b.c",
        ]
    );
    assert_eq!(found[5].line, 5);
    let mut broken = broken_links(&files, &[PathBuf::from("README.md")]);
    broken.sort();
    assert_eq!(
        broken,
        [
            "README.md:5: (docs/gone.md): docs/gone.md does not exist",
            "README.md:5: (docs/guide.md#no-such-step): docs/guide.md has no heading #no-such-step",
            "docs/guide.md:5: (../../x.md): points outside the repository",
            "docs/guide.md:5: (gone.png): docs/gone.png does not exist",
        ]
    );
}
