//! One structural edit of a JSON document: the mutation the checkpoint fuzz
//! target and the replay property test both apply to real checkpoints.

use serde_json::Value;

/// Values and containers in `value`: the places an edit can go.
pub fn places(value: &Value) -> usize {
    1 + match value {
        Value::Array(items) => items.iter().map(places).sum(),
        Value::Object(fields) => fields.values().map(places).sum(),
        _ => 0,
    }
}

/// Apply edit `kind` (any number; taken modulo the edits a value has) to the
/// `target`-th place of `value`, in the order [`places`] counts them.
pub fn edit_at(value: &mut Value, target: usize, kind: u32) {
    let mut at = 0;
    visit(value, target, &mut at, kind);
}

fn visit(value: &mut Value, target: usize, at: &mut usize, kind: u32) -> bool {
    if *at == target {
        edit(value, kind);
        return true;
    }
    *at += 1;
    match value {
        Value::Array(items) => items.iter_mut().any(|v| visit(v, target, at, kind)),
        Value::Object(fields) => fields.values_mut().any(|v| visit(v, target, at, kind)),
        _ => false,
    }
}

/// A number to 0, −1, a huge or fractional value, null or a string; a
/// string emptied or doubled; an array emptied, cut, grown or reversed; a
/// field removed.
fn edit(value: &mut Value, kind: u32) {
    match value {
        Value::Number(_) | Value::Bool(_) | Value::Null => {
            *value = match kind % 8 {
                0 => Value::from(0),
                1 => Value::from(-1),
                2 => Value::from(u64::MAX),
                3 => Value::from(1e308),
                4 => Value::from(0.5),
                5 => Value::from(i64::MIN),
                6 => Value::Null,
                _ => Value::from("x"),
            }
        }
        Value::String(s) => match kind % 3 {
            0 => s.clear(),
            1 => *s = s.repeat(2),
            _ => *value = Value::from(0),
        },
        Value::Array(items) => match kind % 5 {
            0 => items.clear(),
            1 => {
                items.pop();
            }
            2 => {
                if let Some(first) = items.first().cloned() {
                    items.push(first);
                }
            }
            3 => items.reverse(),
            _ => items.truncate(items.len() / 2),
        },
        Value::Object(fields) => {
            let keys: Vec<String> = fields.keys().cloned().collect();
            if let Some(key) = keys.get(kind as usize % keys.len().max(1)) {
                fields.remove(key);
            }
        }
    }
}
