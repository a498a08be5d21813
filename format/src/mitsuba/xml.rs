//! Reading Mitsuba 3 XML elements: `$name` substitution from `<default>`s, typed parameter
//! values (`float`, `integer`, `boolean`, `string`, `rgb`/`spectrum`, `point`, `transform`), and
//! errors that name the file, the line and the element.

use std::collections::HashMap;

use roxmltree::{Document, Node};

use super::transform::{Affine, V3};
use crate::LoadError;

/// The tags of Mitsuba 3 parameter elements (everything else with a `type` is an object).
pub(crate) const PARAM_TAGS: [&str; 9] =
    ["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

/// One step of a `<transform>`, in document order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    Matrix(Affine),
    Translate(V3),
    Rotate(V3, f64),
    Scale(V3),
    LookAt { origin: [f32; 3], target: [f32; 3], up: [f32; 3] },
}

/// The document being read: its file name (for errors) and `<default>` values.
pub(crate) struct Reader<'a, 'input> {
    pub file: &'a str,
    pub doc: &'a Document<'input>,
    pub defaults: HashMap<String, String>,
}

/// `<tag type="..." name="..." id="...">` of an element, short and on one line.
pub(crate) fn describe(node: Node) -> String {
    let mut s = format!("<{}", node.tag_name().name());
    for key in ["type", "name", "id"] {
        if let Some(v) = node.attribute(key) {
            let v: String = v.chars().take(40).flat_map(char::escape_debug).collect();
            s += &format!(" {key}=\"{v}\"");
        }
    }
    s.push('>');
    s
}

impl<'a, 'input> Reader<'a, 'input> {
    /// An error at `node`: `file:line: <element>: reason`.
    pub(crate) fn error(&self, node: Node, reason: impl Into<String>) -> LoadError {
        let line = self.doc.text_pos_at(node.range().start).row;
        LoadError { file: format!("{}:{line}", self.file), entry: describe(node), reason: reason.into() }
    }

    /// Attribute `key` with `$name` references replaced by their `<default>` values.
    pub(crate) fn attr(&self, node: Node, key: &str) -> Result<Option<String>, LoadError> {
        let Some(raw) = node.attribute(key) else { return Ok(None) };
        if !raw.contains('$') {
            return Ok(Some(raw.to_string()));
        }
        let mut out = String::new();
        let mut rest = raw;
        while let Some(i) = rest.find('$') {
            out += &rest[..i];
            let after = &rest[i + 1..];
            let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
            let name = &after[..len];
            let value = self.defaults.get(name).ok_or_else(|| {
                self.error(node, format!("{key}: unknown parameter ${name} (no <default name=\"{name}\">)"))
            })?;
            out += value;
            rest = &after[len..];
        }
        out += rest;
        Ok(Some(out))
    }

    /// A required attribute.
    pub(crate) fn need(&self, node: Node, key: &str) -> Result<String, LoadError> {
        self.attr(node, key)?.ok_or_else(|| self.error(node, format!("missing attribute `{key}`")))
    }

    fn expect_tag(&self, node: Node, tags: &[&str]) -> Result<(), LoadError> {
        if tags.contains(&node.tag_name().name()) {
            Ok(())
        } else {
            Err(self.error(node, format!("expected a <{}> parameter", tags.join("> or <"))))
        }
    }

    fn number<T: std::str::FromStr>(&self, node: Node, key: &str, text: &str) -> Result<T, LoadError> {
        text.trim().parse().map_err(|_| self.error(node, format!("{key}: {text:?} is not a number")))
    }

    fn numbers<T: std::str::FromStr>(&self, node: Node, key: &str, text: &str) -> Result<Vec<T>, LoadError> {
        text.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| self.number(node, key, s))
            .collect()
    }

    /// A `<float>` (or `<integer>`) value, read directly as f32 so that it keeps its bits.
    pub(crate) fn float(&self, node: Node) -> Result<f32, LoadError> {
        self.expect_tag(node, &["float", "integer"])?;
        let v: f32 = self.number(node, "value", &self.need(node, "value")?)?;
        if !v.is_finite() {
            return Err(self.error(node, "value must be finite"));
        }
        Ok(v)
    }

    /// An `<integer>` value in `0..=max`.
    pub(crate) fn count(&self, node: Node, max: u32) -> Result<u32, LoadError> {
        self.expect_tag(node, &["integer"])?;
        let v: i64 = self.number(node, "value", &self.need(node, "value")?)?;
        u32::try_from(v)
            .ok()
            .filter(|&v| v <= max)
            .ok_or_else(|| self.error(node, format!("value {v} is out of range (0 to {max})")))
    }

    /// A `<boolean>` value.
    pub(crate) fn boolean(&self, node: Node) -> Result<bool, LoadError> {
        self.expect_tag(node, &["boolean"])?;
        match self.need(node, "value")?.trim() {
            "true" => Ok(true),
            "false" => Ok(false),
            other => Err(self.error(node, format!("value {other:?} is not true or false"))),
        }
    }

    /// A `<string>` value.
    pub(crate) fn string(&self, node: Node) -> Result<String, LoadError> {
        self.expect_tag(node, &["string"])?;
        self.need(node, "value")
    }

    /// A colour: `<rgb value="r, g, b">` (or one value for grey), `<float>`, or a `<spectrum>`
    /// with one constant value.
    pub(crate) fn color(&self, node: Node) -> Result<[f32; 3], LoadError> {
        self.expect_tag(node, &["rgb", "float", "spectrum"])?;
        let text = self.need(node, "value")?;
        let v: Vec<f32> = self.numbers(node, "value", &text)?;
        let c = match (node.tag_name().name(), v.as_slice()) {
            (_, &[g]) => [g; 3],
            ("rgb", &[r, g, b]) => [r, g, b],
            ("spectrum", _) => {
                return Err(self.error(node, "only a constant spectrum (one value) is modelled; use <rgb>"));
            }
            _ => return Err(self.error(node, format!("value {text:?}: expected 1 or 3 numbers"))),
        };
        if !c.iter().all(|x| x.is_finite()) {
            return Err(self.error(node, "value must be finite"));
        }
        Ok(c)
    }

    /// A `<point>` or `<vector>`: `value="x, y, z"` or attributes `x`, `y`, `z` (default 0).
    pub(crate) fn point(&self, node: Node) -> Result<[f32; 3], LoadError> {
        self.expect_tag(node, &["point", "vector"])?;
        self.xyz(node, 0.0)
    }

    /// Three numbers from `value` (one number means all three) or `x`/`y`/`z` with a default.
    fn xyz<T>(&self, node: Node, default: T) -> Result<[T; 3], LoadError>
    where
        T: std::str::FromStr + Copy + Into<f64>,
    {
        let v = if let Some(text) = self.attr(node, "value")? {
            let v: Vec<T> = self.numbers(node, "value", &text)?;
            match *v.as_slice() {
                [a, b, c] => [a, b, c],
                [a] => [a; 3],
                _ => return Err(self.error(node, format!("value {text:?}: expected 1 or 3 numbers"))),
            }
        } else {
            let mut out = [default; 3];
            for (o, key) in out.iter_mut().zip(["x", "y", "z"]) {
                if let Some(text) = self.attr(node, key)? {
                    *o = self.number(node, key, &text)?;
                }
            }
            out
        };
        if !v.iter().all(|&x| x.into().is_finite()) {
            return Err(self.error(node, "coordinates must be finite"));
        }
        Ok(v)
    }

    /// An attribute holding a 3-vector (`lookat`'s `origin`, `target`, `up`).
    fn vec_attr(&self, node: Node, key: &str) -> Result<[f32; 3], LoadError> {
        let text = self.need(node, key)?;
        let v: Vec<f32> = self.numbers(node, key, &text)?;
        match v.as_slice() {
            &[a, b, c] if v.iter().all(|x| x.is_finite()) => Ok([a, b, c]),
            _ => Err(self.error(node, format!("{key} {text:?}: expected 3 finite numbers"))),
        }
    }

    /// The steps of a `<transform>`, in document order.
    pub(crate) fn transform(&self, node: Node) -> Result<Vec<Op>, LoadError> {
        self.expect_tag(node, &["transform"])?;
        let mut ops = Vec::new();
        for child in node.children().filter(|c| c.is_element()) {
            let op = match child.tag_name().name() {
                "matrix" => {
                    let text = self.need(child, "value")?;
                    let v: Vec<f64> = self.numbers(child, "value", &text)?;
                    if !v.iter().all(|x| x.is_finite()) {
                        return Err(self.error(child, "entries must be finite"));
                    }
                    let m = match v.as_slice() {
                        [a, b, c, d, e, f, g, h, i] => {
                            Affine { m: [[*a, *b, *c, 0.0], [*d, *e, *f, 0.0], [*g, *h, *i, 0.0]] }
                        }
                        [r0 @ .., m30, m31, m32, m33] if r0.len() == 12 => {
                            if [*m30, *m31, *m32, *m33] != [0.0, 0.0, 0.0, 1.0] {
                                return Err(self.error(
                                    child,
                                    "a projective matrix (last row not 0 0 0 1) is not modelled",
                                ));
                            }
                            let row = |r: usize| [r0[4 * r], r0[4 * r + 1], r0[4 * r + 2], r0[4 * r + 3]];
                            Affine { m: [row(0), row(1), row(2)] }
                        }
                        _ => {
                            return Err(
                                self.error(child, format!("expected 16 (or 9) numbers, found {}", v.len()))
                            );
                        }
                    };
                    Op::Matrix(m)
                }
                "translate" => Op::Translate(self.xyz::<f64>(child, 0.0)?),
                "scale" => Op::Scale(self.xyz::<f64>(child, 1.0)?),
                "rotate" => {
                    let axis = self.xyz::<f64>(child, 0.0)?;
                    let angle: f64 = self.number(child, "angle", &self.need(child, "angle")?)?;
                    if !angle.is_finite() {
                        return Err(self.error(child, "angle must be finite"));
                    }
                    Op::Rotate(axis, angle)
                }
                "lookat" => Op::LookAt {
                    origin: self.vec_attr(child, "origin")?,
                    target: self.vec_attr(child, "target")?,
                    up: self.vec_attr(child, "up")?,
                },
                _ => {
                    return Err(self
                        .error(child, "not modelled by picomis (matrix, translate, rotate, scale, lookat)"));
                }
            };
            ops.push(op);
        }
        Ok(ops)
    }

    /// The composed affine map of a `<transform>` (each step applied after the ones before).
    pub(crate) fn affine(&self, node: Node) -> Result<Affine, LoadError> {
        let f = |v: [f32; 3]| v.map(f64::from);
        let mut m = Affine::IDENTITY;
        for op in self.transform(node)? {
            let step = match op {
                Op::Matrix(a) => a,
                Op::Translate(t) => Affine::translate(t),
                Op::Scale(s) => Affine::scale(s),
                Op::Rotate(axis, angle) => Affine::rotate(axis, angle)
                    .ok_or_else(|| self.error(node, "<rotate> needs a non-zero axis"))?,
                Op::LookAt { origin, target, up } => Affine::look_at(f(origin), f(target), f(up))
                    .ok_or_else(|| {
                        self.error(node, "<lookat>: target equals origin or up is parallel to the view")
                    })?,
            };
            m = step.after(&m);
        }
        if !m.is_finite() {
            return Err(self.error(node, "the composed transform is not finite"));
        }
        Ok(m)
    }
}
