//! Reading a value as its option takes it: the one check of every value a front end gives.

use super::option::{End, OptionValue, Read, RenderOption, Values};

impl RenderOption {
    /// `value` read as this option takes it, or what is wrong with it.
    pub(super) fn read(&self, value: &OptionValue) -> Result<Read, String> {
        match self.values {
            Values::Whole { min, max } => {
                let expected = || format!("must be a whole number from {min} to {max}, got {}", shown(value));
                let n = match value {
                    OptionValue::Whole(n) => *n,
                    OptionValue::Text(t) => t.trim().parse::<i128>().map_err(|_| expected())?,
                    _ => return Err(expected()),
                };
                match u64::try_from(n) {
                    Ok(n) if (min..=max).contains(&n) => Ok(Read::Whole(n)),
                    _ => Err(expected()),
                }
            }
            Values::Number { low, high } => {
                let x = match value {
                    OptionValue::Number(x) => Some(*x),
                    OptionValue::Whole(n) => Some(*n as f64),
                    OptionValue::Text(t) => t.trim().parse::<f64>().ok(),
                    OptionValue::List(_) => None,
                };
                match x {
                    Some(x) if within(x, low, high) => Ok(Read::Number(x)),
                    _ => Err(format!(
                        "must be a number in {}, got {}",
                        interval(low, high),
                        shown(value)
                    )),
                }
            }
            Values::Name(names) => match value {
                OptionValue::Text(t) => names
                    .iter()
                    .find(|n| **n == t.trim())
                    .map(|n| Read::Name(n))
                    .ok_or_else(|| format!("expected {}, got {}", alternatives(names), shown(value))),
                _ => Err(format!("expected {}, got {}", alternatives(names), shown(value))),
            },
            Values::Names(names) => {
                let items: Vec<String> = match value {
                    OptionValue::Text(t) => t
                        .split(',')
                        .map(|s| s.trim().to_string())
                        .filter(|s| !s.is_empty())
                        .collect(),
                    OptionValue::List(items) => items
                        .iter()
                        .map(|i| match i {
                            OptionValue::Text(t) => Ok(t.trim().to_string()),
                            other => Err(format!("expected names ({}), got {}", names.join(", "), shown(other))),
                        })
                        .collect::<Result<_, _>>()?,
                    other => return Err(format!("expected names ({}), got {}", names.join(", "), shown(other))),
                };
                let mut read = Vec::new();
                for item in items {
                    let n = names
                        .iter()
                        .find(|n| **n == item)
                        .ok_or_else(|| format!("unknown name '{item}' (expected {})", alternatives(names)))?;
                    if !read.contains(n) {
                        read.push(*n);
                    }
                }
                Ok(Read::Names(read))
            }
            Values::Numbers { min, max, whole } => {
                let count = match min == max {
                    true => format!("{min}"),
                    false => format!("{min} to {max}"),
                };
                let kind = match whole {
                    true => "whole numbers ≥ 0",
                    false => "finite numbers",
                };
                let expected = || format!("expected {} ({count} {kind}), got {}", self.placeholder, shown(value));
                let items: Vec<Option<f64>> = match value {
                    OptionValue::Text(t) => t.split(',').map(|s| s.trim().parse::<f64>().ok()).collect(),
                    OptionValue::List(items) => items
                        .iter()
                        .map(|i| match i {
                            OptionValue::Whole(n) => Some(*n as f64),
                            OptionValue::Number(x) if !whole => Some(*x),
                            _ => None,
                        })
                        .collect(),
                    _ => return Err(expected()),
                };
                let good = |x: &f64| x.is_finite() && (!whole || (*x >= 0.0 && x.fract() == 0.0));
                let items: Vec<f64> = items
                    .into_iter()
                    .map(|x| x.filter(good))
                    .collect::<Option<_>>()
                    .ok_or_else(expected)?;
                match (min..=max).contains(&items.len()) {
                    true => Ok(Read::Numbers(items)),
                    false => Err(expected()),
                }
            }
        }
    }
}

fn within(x: f64, low: End, high: End) -> bool {
    let above = if low.included { x >= low.value } else { x > low.value };
    let below = if high.included { x <= high.value } else { x < high.value };
    above && below && x.is_finite()
}

/// `[a, b)` and the like.
fn interval(low: End, high: End) -> String {
    format!(
        "{}{}, {}{}",
        if low.included { '[' } else { '(' },
        low.value,
        high.value,
        if high.included { ']' } else { ')' }
    )
}

/// `a, b or c`.
fn alternatives(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// A value as a message quotes it.
fn shown(value: &OptionValue) -> String {
    match value {
        OptionValue::Text(t) => format!("'{t}'"),
        OptionValue::Whole(n) => n.to_string(),
        OptionValue::Number(x) => x.to_string(),
        OptionValue::List(items) => format!("[{}]", items.iter().map(shown).collect::<Vec<_>>().join(", ")),
    }
}
