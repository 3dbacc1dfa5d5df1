//! How a fit's verdict ([`crate::study::orders::Verdict`]) is written in a table cell: the order
//! with its mark against the expected one, or the flag that replaces it.

use super::doc::Tone;
use crate::study::orders::{Order, Verdict};

/// The tone and mark of a verdict.
fn mark(v: Verdict) -> (Tone, &'static str) {
    match v {
        Verdict::Meets => (Tone::Good, "✓"),
        Verdict::Below => (Tone::Fair, "~"),
        Verdict::Stalls | Verdict::Grows | Verdict::Flat | Verdict::Irregular => (Tone::Bad, "✗"),
        Verdict::TooFewLevels => (Tone::Missing, "·"),
    }
}

/// What a fit says, in a few words for a table cell: the order with its mark, or the flag.
pub fn cell_text(o: &Order) -> (String, Tone) {
    let v = o.verdict();
    let (tone, m) = mark(v);
    let text = match (v, o.fit) {
        (Verdict::Stalls, Some((order, _))) => format!("{order:.2} {m} stalls"),
        (_, Some((order, _))) if v.is_order() => format!("{order:.2} {m}"),
        (Verdict::Grows, _) => format!("{m} grows"),
        (Verdict::Flat, _) => format!("{m} flat"),
        (Verdict::Irregular, _) => format!("{m} irregular"),
        _ => format!("{m} too few levels"),
    };
    (text, tone)
}
