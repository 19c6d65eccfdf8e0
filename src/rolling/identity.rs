//! What a resumed run must share with the run it continues (issue 53, item 6).
//!
//! `simulate --resume` goes on from the checkpoint's state with the model built again from the
//! case file as it reads now. A case edited between two segments (another speed, another
//! friction coefficient) would carry on a run whose first part ran with other values, and
//! `run.json` would then describe the whole run with the new ones. So a run records what it
//! computed with:
//! - the case as run (`run.json` `settings`), less the fields a resume may change because they
//!   change what is written, not what is computed: the end time, the output times (VTU and
//!   contact-patch snapshots), the checkpoint interval, the name and the description;
//! - the model scenario with its wheel (`run.json` `model_settings`), less its name and
//!   description, and less the file names it reads (their contents are compared instead);
//! - the numerics version of the binary ([`NUMERICS_VERSION`]).
//!
//! A resume compares its own with the earlier record's, field by field, and refuses naming
//! every field that differs ([`differences`]). The checkpoint carries a fingerprint of the
//! three (FNV-1a of their JSON text, [`RunIdentity::fingerprint`]) and the numerics version,
//! so that a resume whose `run.json` was removed or edited, or into whose folder another run's
//! checkpoint was copied, is refused too (`explicit::run`).
//!
//! A record written before this check (no `numerics_version`) holds no model settings and
//! may lack case fields added since (read with their defaults): there only the case fields
//! present in both are compared.

use crate::error::{Error, Result};
use crate::explicit::run::RunStamp;
use crate::model::case::RollingCase;
use crate::scenario::LoadedScenario;
use serde_json::{Map, Value};

/// Version of the numerics of `simulate` (engine, contact, friction, rolling set-up). Raise it
/// with every change that alters the numbers a run computes, so that a run is never carried
/// on by a binary that computes it differently; resume such a run with the binary that started
/// it.
pub const NUMERICS_VERSION: u64 = 1;

/// Case fields a resume may change (they decide what is written and when, not what is
/// computed), as JSON paths.
const RESUMABLE_CASE_FIELDS: [&[&str]; 5] = [
    &["name"],
    &["description"],
    &["end_time_s"],
    &["output", "vtu_times_s"],
    &["output", "patch_times_s"],
];

/// The checkpoint interval: a resume may change it too (a separate list, so that the table
/// above stays one level deep where it can).
const RESUMABLE_OUTPUT_FIELDS: [&str; 1] = ["checkpoint_every_steps"];

/// Model scenario fields that name or describe, without changing the model.
const MODEL_LABEL_FIELDS: [&str; 3] = ["name", "description", "wheel_file"];

/// What a run computes with (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct RunIdentity {
    /// The case less the fields a resume may change.
    pub case: Value,
    /// The model scenario and its wheel, less labels and file names.
    pub model: Value,
}

impl RunIdentity {
    /// The identity of `case` run on `scenario`.
    pub fn of(case: &RollingCase, scenario: &LoadedScenario) -> Result<RunIdentity> {
        let to_value = |what: &str, v: std::result::Result<Value, serde_json::Error>| {
            v.map_err(|e| Error::Numerical(format!("{what} as JSON: {e}")))
        };
        let case = comparable_case(to_value("the case", serde_json::to_value(case))?);
        let model = model_settings(
            to_value(
                "the model scenario",
                serde_json::to_value(&scenario.scenario),
            )?,
            to_value("the wheel", serde_json::to_value(&scenario.wheel))?,
        );
        Ok(RunIdentity { case, model })
    }

    /// FNV-1a (64 bit) of the numerics version and the two JSON texts. serde_json writes an
    /// object's keys in sorted order (no `preserve_order` feature), so the text, and with it
    /// the fingerprint, depends on the values only.
    pub fn fingerprint(&self) -> u64 {
        let text = format!("{NUMERICS_VERSION}\n{}\n{}", self.case, self.model);
        crate::explicit::checkpoint::fnv1a(text.as_bytes())
    }

    /// What the checkpoint stores.
    pub fn stamp(&self) -> RunStamp {
        RunStamp {
            fingerprint: self.fingerprint(),
            numerics_version: NUMERICS_VERSION,
        }
    }
}

/// `model_settings` of `run.json`: the scenario (less [`MODEL_LABEL_FIELDS`]) with the wheel
/// it loaded under `wheel`.
fn model_settings(mut scenario: Value, wheel: Value) -> Value {
    if let Some(map) = scenario.as_object_mut() {
        for field in MODEL_LABEL_FIELDS {
            map.remove(field);
        }
        map.insert("wheel".into(), wheel);
    }
    scenario
}

/// The case as JSON less [`RESUMABLE_CASE_FIELDS`] and [`RESUMABLE_OUTPUT_FIELDS`].
pub fn comparable_case(mut case: Value) -> Value {
    for path in RESUMABLE_CASE_FIELDS {
        remove_path(&mut case, path);
    }
    for field in RESUMABLE_OUTPUT_FIELDS {
        remove_path(&mut case, &["output", field]);
    }
    case
}

fn remove_path(value: &mut Value, path: &[&str]) {
    let Some((last, parents)) = path.split_last() else {
        return;
    };
    let mut at = value;
    for p in parents {
        match at.get_mut(*p) {
            Some(next) => at = next,
            None => return,
        }
    }
    if let Some(map) = at.as_object_mut() {
        map.remove(*last);
    }
}

/// How a resume's identity differs from the `earlier` record's: one line per field, `path:
/// earlier -> now`. Empty when they agree. `earlier` is a `run.json`; one written before this
/// check (no `numerics_version`) is compared on the case fields both hold (module docs).
pub fn differences(earlier: &Value, now: &RunIdentity) -> Vec<String> {
    let mut out = Vec::new();
    let checked = earlier.get("numerics_version").is_some();
    if let Some(version) = earlier.get("numerics_version") {
        if version.as_u64() != Some(NUMERICS_VERSION) {
            out.push(format!(
                "numerics version: {version} -> {NUMERICS_VERSION} (this binary computes \
                 differently from the one that started the run; resume it with that one)"
            ));
        }
    }
    let earlier_case = comparable_case(earlier.get("settings").cloned().unwrap_or(Value::Null));
    diff_values("", &earlier_case, &now.case, !checked, &mut out);
    if checked {
        let earlier_model = earlier.get("model_settings").unwrap_or(&Value::Null);
        diff_values("model: ", earlier_model, &now.model, false, &mut out);
    }
    out
}

/// Appends `path: a -> b` for every leaf where `a` and `b` differ. With `shared_only`, keys
/// present on one side only are skipped (an older record).
fn diff_values(path: &str, a: &Value, b: &Value, shared_only: bool, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => diff_objects(path, x, y, shared_only, out),
        _ if a == b => {}
        _ => out.push(format!("{}: {} -> {}", path.trim_end_matches('.'), a, b)),
    }
}

fn diff_objects(
    path: &str,
    a: &Map<String, Value>,
    b: &Map<String, Value>,
    shared_only: bool,
    out: &mut Vec<String>,
) {
    let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
    keys.sort();
    keys.dedup();
    for key in keys {
        let inner = format!("{path}{key}.");
        match (a.get(key), b.get(key)) {
            (Some(x), Some(y)) => diff_values(&inner, x, y, shared_only, out),
            _ if shared_only => {}
            (x, y) => {
                let shown = |v: Option<&Value>| v.map_or("(absent)".to_string(), Value::to_string);
                out.push(format!("{path}{key}: {} -> {}", shown(x), shown(y)));
            }
        }
    }
}

/// Refuses a resume whose case, model or numerics differ from the `earlier` record's, naming
/// each field that changed.
pub fn check_resume(earlier: &Value, now: &RunIdentity, source: &str) -> Result<()> {
    let changed = differences(earlier, now);
    if changed.is_empty() {
        return Ok(());
    }
    Err(Error::input(
        source,
        "--resume",
        format!(
            "the run in this folder was computed with other values than the case asks for \
             now, so it cannot go on with them (only the end time, the output times, the \
             checkpoint interval, the name and the description may change on a resume): {}. \
             Put the case back as it was, or start a new run in another folder",
            changed.join("; ")
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn identity() -> RunIdentity {
        RunIdentity {
            case: comparable_case(json!({
                "name": "a", "end_time_s": 0.1, "speed_km_per_h": 30.0,
                "friction": {"law": "coulomb", "mu": 0.45},
                "output": {"sample_rate_hz": 20000.0, "vtu_times_s": [], "checkpoint_every_steps": 20000}
            })),
            model: json!({"track": {"length_m": 3.0}, "wheel": {"material": {"youngs_modulus_pa": 2.1e11}}}),
        }
    }

    fn record(case: Value, model: Value) -> Value {
        json!({"numerics_version": NUMERICS_VERSION, "settings": case, "model_settings": model})
    }

    #[test]
    fn a_resume_may_change_the_end_time_and_the_outputs_but_nothing_else() {
        let now = identity();
        let same = record(
            json!({
                "name": "b", "description": "x", "end_time_s": 0.3, "speed_km_per_h": 30.0,
                "friction": {"law": "coulomb", "mu": 0.45},
                "output": {"sample_rate_hz": 20000.0, "vtu_times_s": [0.05], "checkpoint_every_steps": 5000}
            }),
            now.model.clone(),
        );
        assert_eq!(differences(&same, &now), Vec::<String>::new());
        let mut other = same.clone();
        other["settings"]["friction"]["mu"] = json!(0.3);
        other["settings"]["output"]["sample_rate_hz"] = json!(50000.0);
        other["model_settings"]["wheel"]["material"]["youngs_modulus_pa"] = json!(2.0e11);
        other["numerics_version"] = json!(NUMERICS_VERSION + 1);
        let found = differences(&other, &now);
        assert_eq!(found.len(), 4, "{found:?}");
        assert!(found[0].starts_with("numerics version"), "{found:?}");
        assert!(
            found.contains(&"friction.mu: 0.3 -> 0.45".to_string()),
            "{found:?}"
        );
        assert!(found.contains(&"output.sample_rate_hz: 50000.0 -> 20000.0".to_string()));
        assert!(found.contains(
            &"model: wheel.material.youngs_modulus_pa: 200000000000.0 -> 210000000000.0"
                .to_string()
        ));
        // A field on one side only is named as absent on the other.
        let mut added = same.clone();
        added["settings"]["curving"] = json!({"angle_of_attack_mrad": 10.0});
        assert_eq!(
            differences(&added, &now),
            vec![r#"curving: {"angle_of_attack_mrad":10.0} -> (absent)"#.to_string()]
        );
    }

    /// A record written before the check: no numerics version and no model settings; fields
    /// the case gained since are not held against it, the fields both hold are compared.
    #[test]
    fn an_older_record_is_compared_on_the_case_fields_both_hold() {
        let now = identity();
        let older = json!({"settings": {"speed_km_per_h": 30.0, "friction": {"mu": 0.45}}});
        assert_eq!(differences(&older, &now), Vec::<String>::new());
        let changed = json!({"settings": {"speed_km_per_h": 50.0, "friction": {"mu": 0.45}}});
        assert_eq!(
            differences(&changed, &now),
            vec!["speed_km_per_h: 50.0 -> 30.0".to_string()]
        );
    }

    /// The fingerprint depends on the values, not on the order the keys were written in, and
    /// changes with any one of them.
    #[test]
    fn the_fingerprint_follows_the_values_only() {
        let a = identity();
        let mut b = a.clone();
        // The same case written with its keys in the reverse order.
        let reversed: Vec<String> = a
            .case
            .as_object()
            .unwrap()
            .iter()
            .rev()
            .map(|(k, v)| format!("{k:?}: {v}"))
            .collect();
        b.case = serde_json::from_str(&format!("{{{}}}", reversed.join(", "))).unwrap();
        assert_eq!(a.case, b.case);
        assert_eq!(a.fingerprint(), b.fingerprint());
        b.model["track"]["length_m"] = json!(3.0000001);
        assert_ne!(a.fingerprint(), b.fingerprint());
        assert_eq!(a.stamp().numerics_version, NUMERICS_VERSION);
    }
}
