//! The `run.json` of a run made in segments (`--resume`).
//!
//! A resume rebuilds the model from the case and goes on from the checkpoint's state; it runs
//! no preload and does not measure the loaded wheel again. Its own record would therefore say
//! "no preload", give the unloaded wheel centre and rolling radius, and hold the extremes of its
//! own segment only: the record of the whole run would be lost with the first segment's
//! `run.json`. So the resumed record is merged with the earlier one:
//!
//! - the start of rolling (`preload`, `static_preload`, `model.wheel_centre_m`,
//!   `model.rolling_radius_m`, `model.preload_load_error`, the `initial_*` fields of
//!   `contact_point`) is the earlier record's, when the resume has none of its own;
//! - extremes over the run are the extremes of both: largest of `longest_contact_loss_s`,
//!   `largest_node_shear_over_bound`, `deepest_penetration_m`, `run.max_balance_ratio`, the
//!   `largest_*` fields of `contact_point`; smallest of its `smallest_*` fields; the union of
//!   its `*_range_*` intervals;
//! - everything else (the run's status, the time reached, the last energy, the settings) is the
//!   resume's;
//! - `segments` lists every invocation in order (from and to time, its own steps and the run's
//!   count at its end, wall time, status) and
//!   `total_wall_s` sums their wall times.
//!
//! A run writes its record with each periodic checkpoint too, with status `running`. A record
//! still `running` when a resume reads it is that of a process that ended without writing its
//! own (killed, or the machine stopped): its segment is listed with status `killed`, up to its
//! last checkpoint, which is where the resume goes on from; the steps it ran past that
//! checkpoint were lost and run again, and their wall time is not counted.
//!
//! The records are merged as JSON values, so that a record written by an older binary (with
//! fewer fields) still merges: a field missing on either side is taken from the other.

use serde_json::{json, Map, Value};

/// The fields of `model` that describe the loaded wheel at the start of rolling.
const MODEL_START_FIELDS: [&str; 3] = ["wheel_centre_m", "rolling_radius_m", "preload_load_error"];

/// Top-level extremes over the run: the larger of the two records' values.
const LARGEST_FIELDS: [&str; 3] = [
    "longest_contact_loss_s",
    "largest_node_shear_over_bound",
    "deepest_penetration_m",
];

/// One invocation of a run, as `segments` lists it: the steps it took itself (`steps`) and the
/// run's step count at its end (`steps_at_end`), given the count at its start.
fn segment_of(record: &Value, steps_before: u64) -> Value {
    let run = &record["run"];
    let at_end = run["steps"].as_u64();
    json!({
        "from_s": run["resumed_from_s"].as_f64().unwrap_or(0.0),
        "to_s": run["time_s"],
        "steps": at_end.map(|n| n.saturating_sub(steps_before)),
        "steps_at_end": at_end,
        "wall_s": run["wall_s"],
        "status": run["status"],
    })
}

/// The segments an earlier record holds: its own list, or itself as the first one; a segment
/// still `running` was killed after its last checkpoint (module docs). Segments written before
/// `steps_at_end` existed counted the run's steps at their end in `steps`: they are given
/// their own count.
fn segments_of(record: &Value) -> Vec<Value> {
    let mut list = match record["segments"].as_array() {
        Some(list) => list.clone(),
        None => vec![segment_of(record, 0)],
    };
    let mut before = 0;
    for segment in &mut list {
        if segment["status"] == "running" {
            segment["status"] = json!("killed");
        }
        if segment.get("steps_at_end").is_none() {
            let at_end = segment["steps"].as_u64();
            segment["steps_at_end"] = json!(at_end);
            segment["steps"] = json!(at_end.map(|n| n.saturating_sub(before)));
        }
        before = segment["steps_at_end"].as_u64().unwrap_or(before);
    }
    list
}

/// `record` with its `segments` (itself alone) and `total_wall_s`: the record of a run that
/// did not resume.
pub fn with_segments(mut record: Value) -> Value {
    let segments = vec![segment_of(&record, 0)];
    finish(&mut record, segments);
    record
}

/// The record of a resumed segment merged with the `earlier` record of the same run directory
/// (rules in the module docs).
pub fn merge_resumed(earlier: &Value, mut resumed: Value) -> Value {
    if resumed["preload"].is_null() {
        resumed["preload"] = earlier["preload"].clone();
    }
    if resumed["static_preload"].is_null() {
        resumed["static_preload"] = earlier["static_preload"].clone();
    }
    if let (Some(model), Some(before)) = (
        resumed["model"].as_object_mut(),
        earlier["model"].as_object(),
    ) {
        for field in MODEL_START_FIELDS {
            if let Some(v) = before.get(field).filter(|v| !v.is_null()) {
                model.insert(field.to_string(), v.clone());
            }
        }
    }
    for field in LARGEST_FIELDS {
        resumed[field] = extreme(&earlier[field], &resumed[field], f64::max);
    }
    resumed["run"]["max_balance_ratio"] = extreme(
        &earlier["run"]["max_balance_ratio"],
        &resumed["run"]["max_balance_ratio"],
        f64::max,
    );
    resumed["contact_point"] =
        merge_contact_point(&earlier["contact_point"], &resumed["contact_point"]);
    let mut segments = segments_of(earlier);
    let before = segments
        .last()
        .and_then(|s| s["steps_at_end"].as_u64())
        .unwrap_or(0);
    segments.push(segment_of(&resumed, before));
    finish(&mut resumed, segments);
    resumed
}

/// Sets `segments` and `total_wall_s`.
fn finish(record: &mut Value, segments: Vec<Value>) {
    let total: f64 = segments.iter().filter_map(|s| s["wall_s"].as_f64()).sum();
    if let Some(object) = record.as_object_mut() {
        object.insert("segments".into(), Value::Array(segments));
        object.insert("total_wall_s".into(), json!(total));
    }
}

/// The extreme of two numbers by `pick` (max or min); a number missing on one side is the
/// other's.
fn extreme(a: &Value, b: &Value, pick: fn(f64, f64) -> f64) -> Value {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => json!(pick(x, y)),
        (Some(x), None) => json!(x),
        (None, _) => b.clone(),
    }
}

/// `contact_point` over both segments: the start from the earlier one, the extremes of both.
fn merge_contact_point(earlier: &Value, resumed: &Value) -> Value {
    let (Some(before), Some(now)) = (earlier.as_object(), resumed.as_object()) else {
        return if resumed.is_null() {
            earlier.clone()
        } else {
            resumed.clone()
        };
    };
    let mut out = Map::new();
    let keys = now
        .keys()
        .chain(before.keys().filter(|k| !now.contains_key(*k)));
    for key in keys {
        let (a, b) = (
            before.get(key).unwrap_or(&Value::Null),
            now.get(key).unwrap_or(&Value::Null),
        );
        let merged = if key.starts_with("initial_") {
            if a.is_null() {
                b.clone()
            } else {
                a.clone()
            }
        } else if key.starts_with("smallest_") {
            extreme(a, b, f64::min)
        } else if key.starts_with("largest_") {
            extreme(a, b, f64::max)
        } else if key.contains("_range_") {
            union(a, b)
        } else if b.is_null() {
            a.clone()
        } else {
            b.clone()
        };
        out.insert(key.clone(), merged);
    }
    Value::Object(out)
}

/// The union of two `[low, high]` intervals; one missing: the other.
fn union(a: &Value, b: &Value) -> Value {
    let pair = |v: &Value| -> Option<(f64, f64)> {
        let list = v.as_array()?;
        Some((list.first()?.as_f64()?, list.get(1)?.as_f64()?))
    };
    match (pair(a), pair(b)) {
        (Some((a0, a1)), Some((b0, b1))) => json!([a0.min(b0), a1.max(b1)]),
        (Some(_), None) => a.clone(),
        _ => b.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first_segment() -> Value {
        json!({
            "case": "c",
            "model": {"wheel_centre_m": [2.5, -0.02, 0.458], "rolling_radius_m": 0.4599,
                      "preload_load_error": -6.4e-5, "nodes": 10},
            "preload": null,
            "static_preload": {"iterations": 5},
            "run": {"status": "interrupted", "steps": 100, "time_s": 0.01, "wall_s": 50.0,
                    "max_balance_ratio": 2e-7, "resumed_from_s": null},
            "longest_contact_loss_s": 0.0,
            "largest_node_shear_over_bound": 1.0,
            "deepest_penetration_m": 6.8e-5,
            "contact_point": {"initial_wheel_s_mm": 0.7, "wheel_s_range_mm": [-14.3, 1.2],
                              "smallest_flange_clearance_mm": 3.76, "flange_contact_wheel_y_mm": 4.6}
        })
    }

    fn resumed_segment() -> Value {
        json!({
            "case": "c",
            "model": {"wheel_centre_m": [2.5, -0.003, 0.4599], "rolling_radius_m": 0.46,
                      "preload_load_error": null, "nodes": 10},
            "preload": null,
            "static_preload": null,
            "run": {"status": "completed", "steps": 160, "time_s": 0.016, "wall_s": 20.0,
                    "max_balance_ratio": 1e-7, "resumed_from_s": 0.01},
            "longest_contact_loss_s": 1e-5,
            "largest_node_shear_over_bound": 1.0000000001,
            "deepest_penetration_m": 6.7e-5,
            "contact_point": {"initial_wheel_s_mm": -13.6, "wheel_s_range_mm": [-15.7, -13.3],
                              "smallest_flange_clearance_mm": 3.15, "flange_contact_wheel_y_mm": 4.6}
        })
    }

    #[test]
    fn the_start_of_rolling_comes_from_the_earlier_record() {
        let merged = merge_resumed(&first_segment(), resumed_segment());
        assert_eq!(merged["static_preload"]["iterations"], 5);
        assert_eq!(
            merged["model"]["wheel_centre_m"],
            json!([2.5, -0.02, 0.458])
        );
        assert_eq!(merged["model"]["rolling_radius_m"], 0.4599);
        assert_eq!(merged["model"]["preload_load_error"], -6.4e-5);
        assert_eq!(merged["contact_point"]["initial_wheel_s_mm"], 0.7);
        // What the resume reached is the resume's.
        assert_eq!(merged["run"]["status"], "completed");
        assert_eq!(merged["run"]["time_s"], 0.016);
    }

    #[test]
    fn extremes_cover_both_segments() {
        let merged = merge_resumed(&first_segment(), resumed_segment());
        assert_eq!(merged["deepest_penetration_m"], 6.8e-5);
        assert_eq!(merged["longest_contact_loss_s"], 1e-5);
        assert_eq!(merged["largest_node_shear_over_bound"], 1.0000000001);
        assert_eq!(merged["run"]["max_balance_ratio"], 2e-7);
        assert_eq!(
            merged["contact_point"]["wheel_s_range_mm"],
            json!([-15.7, 1.2])
        );
        assert_eq!(
            merged["contact_point"]["smallest_flange_clearance_mm"],
            3.15
        );
        assert_eq!(merged["contact_point"]["flange_contact_wheel_y_mm"], 4.6);
    }

    #[test]
    fn segments_accumulate_over_resumes() {
        let first = with_segments(first_segment());
        assert_eq!(first["segments"].as_array().unwrap().len(), 1);
        assert_eq!(first["total_wall_s"], 50.0);
        let second = merge_resumed(&first, resumed_segment());
        let mut third_part = resumed_segment();
        third_part["run"]["resumed_from_s"] = json!(0.016);
        third_part["run"]["time_s"] = json!(0.02);
        third_part["run"]["wall_s"] = json!(5.0);
        third_part["run"]["steps"] = json!(200);
        let third = merge_resumed(&second, third_part);
        let segments = third["segments"].as_array().unwrap();
        let spans: Vec<(f64, f64)> = segments
            .iter()
            .map(|s| (s["from_s"].as_f64().unwrap(), s["to_s"].as_f64().unwrap()))
            .collect();
        assert_eq!(spans, vec![(0.0, 0.01), (0.01, 0.016), (0.016, 0.02)]);
        assert_eq!(third["total_wall_s"], 75.0);
        assert_eq!(segments[0]["status"], "interrupted");
        // Each segment's own steps, and the run's count at its end (issue 53, item 16).
        let steps: Vec<(u64, u64)> = segments
            .iter()
            .map(|s| {
                (
                    s["steps"].as_u64().unwrap(),
                    s["steps_at_end"].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(steps, vec![(100, 100), (60, 160), (40, 200)]);
        // The start of rolling survives two resumes.
        assert_eq!(third["static_preload"]["iterations"], 5);
    }

    #[test]
    fn a_segment_left_running_is_listed_as_killed_up_to_its_checkpoint() {
        // The record written at the first segment's last checkpoint (10 ms, 50 s of wall);
        // the process was then killed, so the resume reads it as it was.
        let mut at_checkpoint = first_segment();
        at_checkpoint["run"]["status"] = json!("running");
        let at_checkpoint = with_segments(at_checkpoint);
        assert_eq!(at_checkpoint["segments"][0]["status"], "running");
        let merged = merge_resumed(&at_checkpoint, resumed_segment());
        let segments = merged["segments"].as_array().unwrap();
        assert_eq!(segments.len(), 2);
        assert_eq!(segments[0]["status"], "killed");
        assert_eq!(segments[0]["to_s"], segments[1]["from_s"]);
        assert_eq!(segments[1]["status"], "completed");
        // Its wall time up to the checkpoint counts, and its extremes stay.
        assert_eq!(merged["total_wall_s"], 70.0);
        assert_eq!(merged["run"]["max_balance_ratio"], 2e-7);
        assert_eq!(merged["static_preload"]["iterations"], 5);
    }

    #[test]
    fn a_record_from_an_older_binary_still_merges() {
        // No segments, no contact point, no model start fields: the resume's own values stay.
        let older = json!({"run": {"status": "interrupted", "steps": 100, "time_s": 0.01,
                                   "wall_s": 50.0, "max_balance_ratio": 2e-7}});
        let merged = merge_resumed(&older, resumed_segment());
        assert_eq!(merged["model"]["rolling_radius_m"], 0.46);
        assert_eq!(merged["contact_point"]["initial_wheel_s_mm"], -13.6);
        assert_eq!(merged["deepest_penetration_m"], 6.7e-5);
        assert_eq!(merged["segments"].as_array().unwrap().len(), 2);
        assert_eq!(merged["segments"][0]["from_s"], 0.0);
        // Segments listed before `steps_at_end` existed held the count at their end.
        let listed = json!({"run": {"status": "completed", "steps": 160, "time_s": 0.016},
            "segments": [{"from_s": 0.0, "to_s": 0.01, "steps": 100, "status": "interrupted"},
                         {"from_s": 0.01, "to_s": 0.016, "steps": 160, "status": "completed"}]});
        let mut next = resumed_segment();
        next["run"]["steps"] = json!(200);
        let merged = merge_resumed(&listed, next);
        let own: Vec<u64> = merged["segments"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["steps"].as_u64().unwrap())
            .collect();
        assert_eq!(own, vec![100, 60, 40]);
    }
}
