//! Where a byte of a TOML document lies, named as a person names it: `light[1].intensity`,
//! `film.width`. A scene handed over as text that nobody wrote by hand (the Python module's
//! `Scene` and normal-map calls write their dicts as TOML) reports its errors by key, not by a
//! line and column of text its user never saw.

use std::ops::Range;

use toml_edit::{ImDocument, Item, Table, Value};

/// The innermost table, array element or key-value pair of `text` that holds byte `offset`, as
/// a key path; `None` when the text does not parse or nothing holds the offset.
pub fn key_path_at(text: &str, offset: usize) -> Option<String> {
    let doc = ImDocument::parse(text).ok()?;
    let mut innermost = Innermost { offset, best: None };
    innermost.table(doc.as_table(), "");
    innermost.best.map(|(_, path)| path)
}

/// The search: the shortest span holding the offset so far, and its path.
struct Innermost {
    offset: usize,
    best: Option<(usize, String)>,
}

impl Innermost {
    fn consider(&mut self, span: Option<Range<usize>>, path: &str) {
        let Some(span) = span else { return };
        let holds = span.contains(&self.offset) || span.start == self.offset;
        let shorter = self.best.as_ref().is_none_or(|(len, _)| span.len() <= *len);
        if holds && shorter && !path.is_empty() {
            self.best = Some((span.len(), path.to_string()));
        }
    }

    fn table(&mut self, table: &Table, path: &str) {
        self.consider(table.span(), path);
        for (key, item) in table.iter() {
            let child = join(path, key);
            let key_span = table.key(key).and_then(|k| k.span());
            match item {
                Item::Table(t) => self.table(t, &child),
                Item::ArrayOfTables(tables) => {
                    for (i, t) in tables.iter().enumerate() {
                        self.table(t, &format!("{child}[{i}]"));
                    }
                }
                Item::Value(v) => {
                    self.consider(joined(key_span, v.span()), &child);
                    self.value(v, &child);
                }
                Item::None => {}
            }
        }
    }

    fn value(&mut self, value: &Value, path: &str) {
        match value {
            Value::Array(items) => {
                for (i, v) in items.iter().enumerate() {
                    let child = format!("{path}[{i}]");
                    self.consider(v.span(), &child);
                    self.value(v, &child);
                }
            }
            Value::InlineTable(t) => {
                for (key, v) in t.iter() {
                    let child = join(path, key);
                    self.consider(joined(t.key(key).and_then(|k| k.span()), v.span()), &child);
                    self.value(v, &child);
                }
            }
            _ => {}
        }
    }
}

/// `path.key`, or `key` at the top.
fn join(path: &str, key: &str) -> String {
    match path.is_empty() {
        true => key.to_string(),
        false => format!("{path}.{key}"),
    }
}

/// From the key's start to the value's end (either alone if the other is missing).
fn joined(key: Option<Range<usize>>, value: Option<Range<usize>>) -> Option<Range<usize>> {
    match (key, value) {
        (Some(k), Some(v)) => Some(k.start.min(v.start)..k.end.max(v.end)),
        (k, v) => k.or(v),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_name_the_innermost_key() {
        let text = "[film]\nwidth = 64\n\n[[light]]\ntype = \"point\"\n\n[[light]]\nintensity = nan\n\
                    position = [1.0, 2.0, 3.0]\ncolor = { r = 1 }\n";
        let at = |needle: &str| key_path_at(text, text.find(needle).unwrap());
        assert_eq!(at("64").as_deref(), Some("film.width"));
        assert_eq!(at("width").as_deref(), Some("film.width"));
        assert_eq!(at("\"point\"").as_deref(), Some("light[0].type"));
        assert_eq!(at("nan").as_deref(), Some("light[1].intensity"));
        assert_eq!(at("2.0").as_deref(), Some("light[1].position[1]"));
        assert_eq!(at("r = 1").as_deref(), Some("light[1].color.r"));
        assert_eq!(key_path_at("a = [", 0), None);
    }
}
