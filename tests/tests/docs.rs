//! The documentation's links resolve: every relative link and image of `README.md` and of every
//! markdown file under `docs/` names a file or folder of the repository; a link to a markdown
//! file's `#anchor` names one of its headings (GitHub's anchors); a link to a source file's
//! `#L12` or `#L12-L20` stays within the file; and a link whose text is one code span naming an
//! item (`` [`Heuristic::weights`](kernel/src/integrator/mis.rs) ``) points at the file that
//! defines it (`fn weights`, `struct ...`, ...: so a renamed function breaks the link). Links with
//! a scheme (`https:`, `mailto:`) are not followed. Fenced code blocks and inline code are not
//! read as markdown.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The documents whose links are checked: README.md and every markdown file under docs/.
fn documents(root: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("a directory entry").path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p);
            }
        }
    }
    let mut docs = vec![root.join("README.md")];
    walk(&root.join("docs"), &mut docs);
    docs
}

/// A link found in a document: its line, its text (between the brackets) and its target.
#[derive(Debug, PartialEq)]
struct Link {
    line: usize,
    text: String,
    target: String,
}

/// The lines of `md` that are markdown (not inside a fenced code block), with their numbers.
fn markdown_lines(md: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut fence: Option<&str> = None;
    md.lines().enumerate().filter_map(move |(i, line)| {
        let t = line.trim_start();
        for marker in ["```", "~~~"] {
            if t.starts_with(marker) {
                match fence {
                    None => fence = Some(marker),
                    Some(open) if open == marker => fence = None,
                    Some(_) => {}
                }
                return None;
            }
        }
        if fence.is_some() { None } else { Some((i + 1, line)) }
    })
}

/// For each byte of `line`, whether it lies inside an inline code span (backticks included).
fn code_mask(line: &[u8]) -> Vec<bool> {
    let mut mask = vec![false; line.len()];
    let mut i = 0;
    while i < line.len() {
        if line[i] != b'`' {
            i += 1;
            continue;
        }
        let run = line[i..].iter().take_while(|&&c| c == b'`').count();
        // The closing run of the same length, if any; else the backticks are literal.
        let mut j = i + run;
        let mut close = None;
        while j < line.len() {
            if line[j] == b'`' {
                let r = line[j..].iter().take_while(|&&c| c == b'`').count();
                if r == run {
                    close = Some(j + r);
                    break;
                }
                j += r;
            } else {
                j += 1;
            }
        }
        match close {
            Some(end) => {
                mask[i..end].iter_mut().for_each(|m| *m = true);
                i = end;
            }
            None => i += run,
        }
    }
    mask
}

/// The inline links and images of `md` (`[text](target)`, `![alt](target)`; a title after the
/// target is dropped).
fn links(md: &str) -> Vec<Link> {
    let mut out = Vec::new();
    for (n, line) in markdown_lines(md) {
        let b = line.as_bytes();
        let code = code_mask(b);
        for i in 0..b.len().saturating_sub(1) {
            if code[i] || b[i] != b']' || b[i + 1] != b'(' {
                continue;
            }
            // The '[' that opens this link's text.
            let mut depth = 0;
            let mut open = None;
            for k in (0..i).rev() {
                if code[k] {
                    continue;
                }
                match b[k] {
                    b']' => depth += 1,
                    b'[' if depth == 0 => {
                        open = Some(k);
                        break;
                    }
                    b'[' => depth -= 1,
                    _ => {}
                }
            }
            let Some(open) = open else { continue };
            // The ')' that closes the target (parentheses inside it balanced).
            let mut depth = 0;
            let mut close = None;
            for (k, &c) in b.iter().enumerate().skip(i + 2) {
                match c {
                    b'(' => depth += 1,
                    b')' if depth == 0 => {
                        close = Some(k);
                        break;
                    }
                    b')' => depth -= 1,
                    _ => {}
                }
            }
            let Some(close) = close else { continue };
            let inside = line[i + 2..close].trim();
            let target = inside.split_whitespace().next().unwrap_or("");
            let target = target.trim_start_matches('<').trim_end_matches('>');
            out.push(Link { line: n, text: line[open + 1..i].to_string(), target: target.to_string() });
        }
    }
    out
}

/// GitHub's anchor of a heading: its text as rendered (code spans, links and emphasis reduced to
/// their text), lower case, every character but letters, digits, `-`, `_` and spaces dropped,
/// spaces turned into `-`.
fn slug(heading: &str) -> String {
    // Links: keep the text between the brackets.
    let mut text = String::new();
    let mut rest = heading;
    while let Some(start) = rest.find('[') {
        let (before, after) = rest.split_at(start);
        text.push_str(before);
        match (after.find("]("), after.find(')')) {
            (Some(mid), Some(_)) => {
                text.push_str(&after[1..mid]);
                let tail = &after[mid + 2..];
                rest = tail.find(')').map_or("", |e| &tail[e + 1..]);
            }
            _ => {
                text.push_str(after);
                rest = "";
            }
        }
    }
    text.push_str(rest);
    text.trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of the headings of `md`, as GitHub makes them (a repeated one gets `-1`, `-2`, ...).
fn anchors(md: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for (_, line) in markdown_lines(md) {
        let hashes = line.bytes().take_while(|&c| c == b'#').count();
        if !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let base = slug(line[hashes..].trim().trim_end_matches('#'));
        let n = seen.entry(base.clone()).or_insert(0);
        out.push(if *n == 0 { base.clone() } else { format!("{base}-{n}") });
        *n += 1;
    }
    out
}

/// Whether `source` defines the item `name` (a function, type, trait, module, constant or macro).
fn defines(source: &str, name: &str) -> bool {
    const KINDS: [&str; 9] =
        ["fn ", "struct ", "enum ", "trait ", "type ", "mod ", "const ", "static ", "macro_rules! "];
    KINDS.iter().any(|kind| {
        let pattern = format!("{kind}{name}");
        source.match_indices(&pattern).any(|(at, _)| {
            let next = source[at + pattern.len()..].chars().next();
            let before = source[..at].chars().next_back();
            !next.is_some_and(|c| c.is_alphanumeric() || c == '_')
                && !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
    })
}

/// The item a link's text names, if the text is one code span of a Rust path
/// (`` `Heuristic::weights` ``, `` `Direct<...>` ``): its last segment.
fn item_named(text: &str) -> Option<&str> {
    let code = text.strip_prefix('`')?.strip_suffix('`')?;
    let path = code.split('<').next()?.trim();
    let ok = !path.is_empty() && path.chars().all(|c| c.is_alphanumeric() || c == '_' || c == ':');
    let last = path.rsplit("::").next()?;
    (ok && last.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')).then_some(last)
}

/// `path` with `.` and `..` resolved lexically.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// Every broken link of the document `doc` (text `md`), as failures naming the file and line.
fn broken_links(root: &Path, doc: &Path, md: &str) -> Vec<String> {
    let name = doc.strip_prefix(root).unwrap_or(doc).display().to_string();
    let mut failures = Vec::new();
    for link in links(md) {
        let fail = |why: String| format!("{name}:{}: ({}) {why}", link.line, link.target);
        let target = link.target.as_str();
        if target.is_empty() {
            failures.push(fail("empty link".into()));
            continue;
        }
        if target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((p, a)) => (p, Some(a)),
            None => (target, None),
        };
        if path.is_empty() {
            // An anchor in the document itself.
            let anchor = anchor.unwrap_or("");
            if !anchors(md).iter().any(|a| a == anchor) {
                failures.push(fail(format!("no heading with the anchor #{anchor}")));
            }
            continue;
        }
        let file = normalize(&doc.parent().unwrap_or(root).join(path));
        if !file.starts_with(normalize(root)) {
            failures.push(fail("leaves the repository".into()));
            continue;
        }
        if !file.exists() {
            failures.push(fail(format!("{} does not exist", file.display())));
            continue;
        }
        let is_md = file.extension().is_some_and(|x| x == "md");
        if let Some(anchor) = anchor {
            if is_md {
                let text = std::fs::read_to_string(&file).unwrap_or_default();
                if !anchors(&text).iter().any(|a| a == anchor) {
                    failures.push(fail(format!("no heading with the anchor #{anchor}")));
                }
            } else {
                let lines = std::fs::read_to_string(&file).map(|t| t.lines().count()).unwrap_or(0);
                let numbers: Option<Vec<usize>> =
                    anchor.split('-').map(|l| l.strip_prefix('L').and_then(|n| n.parse().ok())).collect();
                match numbers {
                    Some(n) if !n.is_empty() && n.iter().all(|l| (1..=lines).contains(l)) => {}
                    _ => failures.push(fail(format!("#{anchor} is not a line of the file ({lines} lines)"))),
                }
            }
        }
        if let Some(item) = item_named(&link.text) {
            let source = file.extension().is_some_and(|x| x == "rs");
            let stem = file.file_stem().is_some_and(|s| s == item);
            if source && !stem && !defines(&std::fs::read_to_string(&file).unwrap_or_default(), item) {
                failures.push(fail(format!("{} defines no item `{item}`", file.display())));
            }
        }
    }
    failures
}

#[test]
fn every_relative_link_of_the_docs_resolves() {
    let root = root();
    let docs = documents(&root);
    assert!(docs.len() > 10, "README.md and the docs/ pages: found {}", docs.len());
    let mut failures = Vec::new();
    let mut checked = 0;
    for doc in &docs {
        let md = std::fs::read_to_string(doc).unwrap_or_else(|e| panic!("{}: {e}", doc.display()));
        checked += links(&md).len();
        failures.extend(broken_links(&root, doc, &md));
    }
    // Not vacuous: the README alone links into docs/ and the kernel.
    assert!(checked > 100, "only {checked} links found");
    assert!(failures.is_empty(), "{} broken links:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn every_docs_page_is_reachable_from_the_readme() {
    let root = root();
    let mut reached = vec![normalize(&root.join("README.md"))];
    let mut i = 0;
    while i < reached.len() {
        let doc = reached[i].clone();
        let md = std::fs::read_to_string(&doc).unwrap_or_default();
        for link in links(&md) {
            let path = link.target.split('#').next().unwrap_or("");
            if path.is_empty() || path.contains("://") {
                continue;
            }
            let file = normalize(&doc.parent().unwrap_or(&root).join(path));
            if file.extension().is_some_and(|x| x == "md") && !reached.contains(&file) {
                reached.push(file);
            }
        }
        i += 1;
    }
    let unreached: Vec<String> = documents(&root)
        .iter()
        .map(|d| normalize(d))
        .filter(|d| !reached.contains(d))
        .map(|d| d.strip_prefix(normalize(&root)).unwrap_or(&d).display().to_string())
        .collect();
    assert!(unreached.is_empty(), "docs pages no link chain from README.md reaches: {unreached:?}");
}

/// The checker finds what it must: each kind of broken link in a document made for the purpose.
#[test]
fn the_link_check_can_fail() {
    let root = root();
    let doc = root.join("docs").join("made-up.md");
    let md = "# Title\n\
        [fine](../README.md) [fine](#title) [fine](mis.md#the-weights) \
        [`Heuristic::weights`](../kernel/src/integrator/mis.rs)\n\
        [missing](no-such-file.md)\n\
        [bad anchor](mis.md#no-such-heading)\n\
        [bad line](../kernel/src/lib.rs#L999999)\n\
        [`Heuristic::no_such_function`](../kernel/src/integrator/mis.rs)\n\
        `[in code](no-such-file.md)`\n\
        ```\n[in a fence](no-such-file.md)\n```\n\
        [web](https://example.invalid/)\n";
    let failures = broken_links(&root, &doc, md);
    assert_eq!(failures.len(), 4, "{failures:#?}");
    for (failure, line) in failures.iter().zip([3, 4, 5, 6]) {
        assert!(failure.starts_with(&format!("docs/made-up.md:{line}:")), "{failure}");
    }
}

#[test]
fn anchors_are_githubs() {
    let md = "# picomis\n## The device's display: `picomis-sim view`\n### Summary: the best of each, per scene\n\
        ## Reading\n## Reading\n```\n# not a heading\n```\n#not a heading either\n## A [link](x.md) in it\n";
    assert_eq!(
        anchors(md),
        [
            "picomis",
            "the-devices-display-picomis-sim-view",
            "summary-the-best-of-each-per-scene",
            "reading",
            "reading-1",
            "a-link-in-it"
        ]
    );
    assert_eq!(item_named("`Direct<Lights<Sel, Sp, Q, Lb>, Cv, Md, Src>`"), Some("Direct"));
    assert_eq!(item_named("`picomis_host::renderer`"), Some("renderer"));
    assert_eq!(item_named("`kernel/src/lib.rs`"), None);
    assert_eq!(item_named("all techniques"), None);
    assert!(defines("pub fn weights<const N: usize>(", "weights"));
    assert!(!defines("pub fn weights_of(", "weights"));
}
