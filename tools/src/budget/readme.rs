//! docs/firmware.md with its generated block replaced, and the difference shown when the
//! committed block is not the generated one.

use std::fmt::Write as _;

use super::table::{BEGIN, END};

/// `doc` with the lines from [`BEGIN`] to [`END`] replaced by `block` (which ends in a newline),
/// ending in exactly one newline; `Err(marker)` if a marker line is missing.
pub fn with_block(doc: &str, block: &str) -> Result<String, &'static str> {
    let lines: Vec<&str> = doc.strip_suffix('\n').unwrap_or(doc).split('\n').collect();
    if let Some(marker) = [BEGIN, END].into_iter().find(|marker| !lines.contains(marker)) {
        return Err(marker);
    }
    let mut out = String::new();
    let mut inside = false;
    for line in lines {
        if line == BEGIN {
            out.push_str(block);
            inside = true;
        } else if line == END {
            inside = false;
        } else if !inside {
            out.push_str(line);
            out.push('\n');
        }
    }
    let kept = out.trim_end_matches('\n').len();
    out.truncate(kept);
    out.push('\n');
    Ok(out)
}

/// The lines that differ between `old` and `new` as one hunk of a unified diff (the common start
/// and end left out but for three lines of context); empty if they are equal.
pub fn diff(old: &str, new: &str, old_name: &str, new_name: &str) -> String {
    const CONTEXT: usize = 3;
    if old == new {
        return String::new();
    }
    let a: Vec<&str> = old.split_inclusive('\n').collect();
    let b: Vec<&str> = new.split_inclusive('\n').collect();
    let start = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let end = a[start..].iter().rev().zip(b[start..].iter().rev()).take_while(|(x, y)| x == y).count();
    let (a_end, b_end) = (a.len() - end, b.len() - end);
    let (from, to) = (start.saturating_sub(CONTEXT), (a_end + CONTEXT).min(a.len()));
    let after = to - a_end;
    let mut out = format!("--- {old_name}\n+++ {new_name}\n");
    let _ = writeln!(out, "@@ -{},{} +{},{} @@", from + 1, to - from, from + 1, b_end + after - from);
    let hunk = a[from..start].iter().map(|line| (' ', line));
    let hunk = hunk.chain(a[start..a_end].iter().map(|line| ('-', line)));
    let hunk = hunk.chain(b[start..b_end].iter().map(|line| ('+', line)));
    for (sign, line) in hunk.chain(a[a_end..to].iter().map(|line| (' ', line))) {
        out.push(sign);
        out.push_str(line);
        if !line.ends_with('\n') {
            out.push_str("\n\\ No newline at end of file\n");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(block: &str) -> String {
        format!("# Firmware\n\ntext\n{BEGIN}\n{block}{END}\n\nmore\n")
    }

    #[test]
    fn replaces_the_block_only() {
        let new = format!("{BEGIN}\n| new |\n{END}\n");
        let replaced = with_block(&doc("| old |\n| rows |\n"), &new).unwrap();
        assert_eq!(replaced, doc("| new |\n"));
        // Generated again, the same: what `readme --check` compares.
        assert_eq!(with_block(&replaced, &new).unwrap(), replaced);
        // One newline at the end, as many as there were.
        assert_eq!(with_block(&format!("{}\n\n", doc("")), &new).unwrap(), replaced);
        assert_eq!(with_block(doc("").trim_end(), &new).unwrap(), replaced);
    }

    #[test]
    fn markers_are_whole_lines() {
        let block = format!("{BEGIN}\n{END}\n");
        assert_eq!(with_block("no markers\n", &block), Err(BEGIN));
        assert_eq!(with_block(&format!("{BEGIN}\n"), &block), Err(END));
        assert_eq!(with_block(&format!(" {BEGIN}\n{END}\n"), &block), Err(BEGIN));
    }

    #[test]
    fn diff_shows_the_changed_lines() {
        assert_eq!(diff("a\nb\n", "a\nb\n", "old", "new"), "");
        let changed = diff("1\n2\n3\n4\nx\n5\n6\n7\n8\n", "1\n2\n3\n4\ny\nz\n5\n6\n7\n8\n", "old", "new");
        assert_eq!(changed, "--- old\n+++ new\n@@ -2,7 +2,8 @@\n 2\n 3\n 4\n-x\n+y\n+z\n 5\n 6\n 7\n");
        let added = diff("a\nb\n", "a\nnew\nb\n", "old", "new");
        assert_eq!(added, "--- old\n+++ new\n@@ -1,2 +1,3 @@\n a\n+new\n b\n");
        let removed = diff("a\ngone\nb\n", "a\nb\n", "old", "new");
        assert_eq!(removed, "--- old\n+++ new\n@@ -1,3 +1,2 @@\n a\n-gone\n b\n");
        let newline = diff("a\nb", "a\nb\n", "old", "new");
        assert_eq!(newline, "--- old\n+++ new\n@@ -1,2 +1,2 @@\n a\n-b\n\\ No newline at end of file\n+b\n");
    }
}
