//! The phase-resolved field of a run on a sawtooth base on disk (`events::phase_field`): the
//! ratchet paper's momentum and mass density fields over one tooth (seed 004, Figs 13-14).
//! `phase_fields.csv` holds every frame and box; `phase_fields.png` draws the six frames,
//! arrows for the momentum density and disks whose radii grow with the mass density, over the
//! tooth's profile.

use analysis::plot::{FieldPanel, FieldPlot};
use events::phase_field::PhaseField;
use events::Sawtooth;

use crate::rundir::output::{CliError, RunDir};

/// The plot's title, true to what it draws: the field is folded onto one tooth and drawn
/// over `teeth` repeats of it.
fn title(teeth: usize, samples: u64) -> String {
    let over = if teeth == 1 {
        "over one tooth".to_string()
    } else {
        format!("folded onto one tooth, drawn over {teeth} teeth (the same tooth repeated)")
    };
    format!("Momentum (arrows) and mass (disks) density {over}, by drive phase ({samples} samples)")
}

/// Writes the field's table and plot (nothing when no frame has samples).
pub fn write(dir: &mut RunDir, field: &PhaseField, base: &Sawtooth) -> Result<(), CliError> {
    let mut rows = Vec::new();
    let mut frames = Vec::new();
    for frame in 0..field.frames {
        let boxes = field.rows(frame);
        for b in &boxes {
            rows.push(vec![frame as f64, field.samples[frame] as f64, b[0], b[1], b[2], b[3], b[4]]);
        }
        if !boxes.is_empty() {
            frames.push((frame, boxes));
        }
    }
    // The picture shows the dense layer: up to the height below which 80 % of the mass lies
    // (at least twice the tooth), over as many teeth (repeats of the folded one) as keep the
    // axes' scales near equal.
    let mut top: f64 = 2.0 * base.height;
    for (_, boxes) in &frames {
        let total: f64 = boxes.iter().map(|b| b[2]).sum();
        let mut below = 0.0;
        for b in boxes {
            below += b[2];
            if below >= 0.8 * total {
                top = top.max(b[1] + 0.5 * field.side());
                break;
            }
        }
    }
    let w = base.width;
    let teeth = (top / w).round().clamp(1.0, 4.0) as usize;
    let degrees = 360.0 / field.frames as f64;
    let panels = frames
        .iter()
        .map(|(frame, boxes)| {
            let shown = || {
                boxes
                    .iter()
                    .filter(|b| b[1] < top)
                    .flat_map(|b| (0..teeth).map(move |k| (b[0] + k as f64 * w, b)))
            };
            FieldPanel {
                title: format!(
                    "j = {frame}: phase {:.0}-{:.0} deg",
                    *frame as f64 * degrees,
                    (frame + 1) as f64 * degrees
                ),
                arrows: shown().map(|(x, b)| (x, b[1], b[3], b[4])).collect(),
                disks: shown().map(|(x, b)| (x, b[1], b[2])).collect(),
            }
        })
        .collect();
    if rows.is_empty() {
        return Ok(());
    }
    dir.csv(
        "phase_fields.csv",
        &["frame", "samples", "x_m", "z_m", "mass_kg_per_m2", "px_kg_per_m_s", "pz_kg_per_m_s"],
        &rows,
    )?;
    let w = base.width;
    let plot = FieldPlot {
        title: title(teeth, field.samples.iter().sum::<u64>()),
        x_label: "x from a valley (m)".into(),
        y_label: "z above the valleys (m)".into(),
        x: 0.0..teeth as f64 * w,
        y: 0.0..top,
        reach: 0.9 * field.side(),
        outline: (0..teeth)
            .flat_map(|k| {
                let x0 = k as f64 * w;
                [(x0, 0.0), (x0 + base.asymmetry * w, base.height), (x0 + w, 0.0)]
            })
            .collect(),
        panels,
        columns: 3,
    };
    let files = plot
        .save(&dir.path.join("phase_fields"))
        .map_err(|e| format!("cannot draw phase_fields: {e}"))?;
    dir.note_files(files);
    Ok(())
}

#[cfg(test)]
mod tests {
    /// Issue 43: `phase_fields.png` said "over one tooth" while it drew four; the title says
    /// how many teeth it draws.
    #[test]
    fn the_title_says_how_many_teeth_are_drawn() {
        assert!(super::title(1, 10).contains("over one tooth, by drive phase (10 samples)"));
        let four = super::title(4, 10);
        assert!(four.contains("drawn over 4 teeth") && !four.contains("over one tooth"), "{four}");
    }
}
