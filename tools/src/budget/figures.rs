//! Figures by key: read from a figures file (`key value` lines, written by scripts/firmware.sh)
//! or from firmware/budget.json; and budget.json's text, written from a figures file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::Number;

use super::error::Error;
use super::keys::{Key, written_keys};

/// budget.json's `generated_by` field.
pub const GENERATED_BY: &str =
    "scripts/firmware.sh measure (do not edit: the table of docs/firmware.md and the budget check read it)";
/// budget.json's `workload` field: what the figures measure.
pub const WORKLOAD: &str = "veach_mis, 1 light + 1 BSDF sample, power heuristic, the lecture preset \
    (PICOMIS_PRESET=lecture; the best_ keys: the best preset, the defaults); instructions per camera \
    sample at 64x48, 1 spp under qemu -icount shift=0 (exact); sizes of the board build (defmt over \
    RTT; M4F 160x120, M0 64x48 framebuffer); peak stack of the QEMU build by stack painting";

/// One figure: the number as written, and its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// The number as the file spells it (printed by the check).
    pub text: String,
    /// Its value.
    pub value: f64,
    number: Number,
}

impl Figure {
    /// A figure from its text, if the text is a JSON number.
    fn parse(text: &str) -> Option<Figure> {
        let number: Number = text.parse().ok()?;
        let value = number.as_f64().filter(|v| v.is_finite())?;
        Some(Figure { text: text.to_string(), value, number })
    }
}

/// The figures of one file, by key.
#[derive(Debug)]
pub struct Figures {
    /// The file they came from (named by the errors).
    path: PathBuf,
    by_key: BTreeMap<String, Figure>,
}

impl Figures {
    /// A figures file: one `key value` line per figure (blank lines skipped; of a key given twice,
    /// the first).
    pub fn from_lines(path: &Path, text: &str) -> Result<Figures, Error> {
        let mut by_key = BTreeMap::new();
        for (i, line) in text.lines().enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            let mut words = line.split_whitespace();
            let figure = match (words.next(), words.next().and_then(Figure::parse), words.next()) {
                (Some(key), Some(figure), None) => (key, figure),
                _ => {
                    return Err(Error::NotAFigure {
                        path: path.to_path_buf(),
                        line: i + 1,
                        text: line.to_string(),
                    });
                }
            };
            by_key.entry(figure.0.to_string()).or_insert(figure.1);
        }
        Ok(Figures { path: path.to_path_buf(), by_key })
    }

    /// firmware/budget.json: an object whose numbers are the figures (its text fields, and any
    /// field that is not a number, are no figures).
    pub fn from_budget_json(path: &Path, text: &str) -> Result<Figures, Error> {
        let object: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(text).map_err(|source| Error::Json { path: path.to_path_buf(), source })?;
        let by_key = object
            .into_iter()
            .filter_map(|(key, value)| match value {
                serde_json::Value::Number(number) => Figure::parse(&number.to_string()).map(|f| (key, f)),
                _ => None,
            })
            .collect();
        Ok(Figures { path: path.to_path_buf(), by_key })
    }

    /// The figure of `key`, or the error naming the file and the key.
    pub fn get(&self, key: Key) -> Result<&Figure, Error> {
        let name = key.to_string();
        self.by_key.get(&name).ok_or(Error::MissingFigure { path: self.path.clone(), key: name })
    }

    /// The value of `key` ([`Figures::get`]).
    pub fn value(&self, key: Key) -> Result<f64, Error> {
        self.get(key).map(|figure| figure.value)
    }
}

/// budget.json's text from `figures`: `generated_by`, `workload`, then every figure key in its
/// order ([`written_keys`]); fails on the first figure missing from `figures`.
pub fn budget_json(figures: &Figures) -> Result<String, Error> {
    let entries = written_keys()
        .into_iter()
        .map(|key| Ok((key.to_string(), &figures.get(key)?.number)))
        .collect::<Result<_, _>>()?;
    let mut text = serde_json::to_string_pretty(&BudgetJson(entries))
        .map_err(|source| Error::Json { path: figures.path.clone(), source })?;
    text.push('\n');
    Ok(text)
}

/// budget.json's object, fields in the file's order.
struct BudgetJson<'a>(Vec<(String, &'a Number)>);

impl Serialize for BudgetJson<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(2 + self.0.len()))?;
        map.serialize_entry("generated_by", GENERATED_BY)?;
        map.serialize_entry("workload", WORKLOAD)?;
        for (key, number) in &self.0 {
            map.serialize_entry(key, number)?;
        }
        map.end()
    }
}

/// A figures file's text without the line of `key` (for the tests of a missing figure).
#[cfg(test)]
pub fn without_key(text: &str, key: &str) -> String {
    text.lines()
        .filter(|line| line.split_whitespace().next() != Some(key))
        .map(|l| format!("{l}\n"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::budget::keys::{CORES, Figure as Kind};

    const FIGURES: &str = include_str!("../../fixtures/budget/figures_mixed.txt");
    /// scripts/budget.sh's (the shell version's) `write` of FIGURES.
    const BUDGET: &str = include_str!("../../fixtures/budget/budget_mixed.json");

    fn figures(text: &str) -> Figures {
        Figures::from_lines(Path::new("figures.txt"), text).unwrap()
    }

    #[test]
    fn writes_the_shell_versions_json() {
        assert_eq!(budget_json(&figures(FIGURES)).unwrap(), BUDGET);
    }

    #[test]
    fn json_round_trip() {
        let from_lines = figures(FIGURES);
        let json = budget_json(&from_lines).unwrap();
        let from_json = Figures::from_budget_json(Path::new("budget.json"), &json).unwrap();
        for key in written_keys() {
            assert_eq!(from_json.get(key).unwrap(), from_lines.get(key).unwrap(), "{key}");
        }
        // The text fields are no figures, and the JSON written again is the same.
        assert_eq!(from_json.by_key.len(), written_keys().len());
        assert_eq!(budget_json(&from_json).unwrap(), json);
        let fields: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(fields["generated_by"], GENERATED_BY);
        assert_eq!(fields["workload"], WORKLOAD);
    }

    #[test]
    fn missing_figure() {
        let without = without_key(FIGURES, "m0_best_flash_text_bytes");
        let err = budget_json(&figures(&without)).unwrap_err();
        assert!(
            matches!(&err, Error::MissingFigure { key, .. } if key == "m0_best_flash_text_bytes"),
            "{err}"
        );
        assert_eq!(err.to_string(), "figures.txt: no figure m0_best_flash_text_bytes");
        let key = Key { core: &CORES[1], figure: Kind::BestFlashText };
        assert!(figures(&without).get(key).is_err());
        assert!(figures(FIGURES).get(key).is_ok());
    }

    #[test]
    fn first_of_a_key_given_twice() {
        let key = Key { core: &CORES[0], figure: Kind::Rodata };
        let twice = figures("m4f_rodata_bytes 10\n\nm4f_rodata_bytes 20\n");
        assert_eq!(twice.get(key).unwrap().text, "10");
    }

    #[test]
    fn not_a_figure() {
        for bad in ["m0_rodata_bytes", "m0_rodata_bytes 1 2", "m0_rodata_bytes 12kB", "m0_rodata_bytes 1.2.3"]
        {
            let err =
                Figures::from_lines(Path::new("f"), &format!("m4f_rodata_bytes 1\n{bad}\n")).unwrap_err();
            assert!(matches!(err, Error::NotAFigure { line: 2, .. }), "{bad}: {err}");
        }
        assert!(Figures::from_budget_json(Path::new("b"), "[1, 2]").is_err());
    }
}
