//! The blast part of `blastsph report`: gauges, crater, snapshots (filled in by the blast work).

use crate::case::Case;
use crate::error::Result;
use crate::output::Frame;
use serde_json::{Value, json};
use std::path::Path;

pub fn report(_dir: &Path, _case: &Case, summary: &Value, _frames: &[Frame]) -> Result<Value> {
    if let Some(c) = summary.get("crater") {
        println!(
            "crater: diameter {:.3} m, depth {:.3} m",
            c["diameter_m"].as_f64().unwrap_or(0.0),
            c["depth_m"].as_f64().unwrap_or(0.0)
        );
    }
    Ok(json!({}))
}
