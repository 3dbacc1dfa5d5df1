//! One look per method across every figure: a space's colour and mark come from its place in
//! [`crate::space::SPACES`], a scheme's from its place in [`crate::time::SCHEMES`], a contact
//! formulation's from [`crate::contact::FORMULATIONS`], so that a method added to a registry gets
//! its own without any change here. Variants of one method in a figure (Newmark β = ½ and ¼, the
//! three Nitsche θ) keep its colour and mark and differ by dash and hollow marks.

use crate::output::plot::{Dash, Style, DASHES, MARKERS, PALETTE};

/// The style of the `k`-th entry of a registry, with colours from `PALETTE[offset..]`; the
/// marks shift by one at each round of the palette, so that entries `PALETTE.len()` apart
/// (the same colour) differ in their mark.
fn nth(k: usize, offset: usize) -> Style {
    Style {
        color: PALETTE[(k + offset) % PALETTE.len()],
        marker: MARKERS[(k + k / PALETTE.len()) % MARKERS.len()],
        dash: Dash::Solid,
        hollow: false,
    }
}

/// `style` for the `variant`-th parameter set of its method in a figure.
fn variant(style: Style, variant: usize) -> Style {
    Style {
        dash: DASHES[variant % DASHES.len()],
        hollow: variant % 2 == 1,
        ..style
    }
}

/// Position of `name` in a registry (past the end for an unknown name, still deterministic).
fn place<'a>(names: impl Iterator<Item = &'a str>, name: &str) -> usize {
    let names: Vec<&str> = names.collect();
    names.iter().position(|n| *n == name).unwrap_or(names.len())
}

/// The style of a space (colours from the start of the palette).
pub fn space(name: &str) -> Style {
    nth(place(crate::space::SPACES.iter().map(|e| e.name), name), 0)
}

/// The style of the `k`-th parameter set of a scheme in a figure (colours after the spaces').
pub fn scheme(name: &str, k: usize) -> Style {
    let n = crate::space::SPACES.len();
    variant(
        nth(place(crate::time::SCHEMES.iter().map(|e| e.name), name), n),
        k,
    )
}

/// The style of the `k`-th parameter set of a contact formulation in a figure; `label` is the
/// formulation's name or its label (`weak_p1`: the name and its multiplier space).
pub fn formulation(label: &str, k: usize) -> Style {
    let names = || crate::contact::FORMULATIONS.iter().map(|e| e.name);
    let name = names()
        .find(|n| label == *n || label.starts_with(&format!("{n}_")))
        .unwrap_or(label);
    let n = crate::space::SPACES.len() + crate::time::SCHEMES.len();
    variant(nth(place(names(), name), n), k)
}

/// The style of the `k`-th of `n` curves of one method (time steps): shades of blue from dark
/// to light, solid.
pub fn sequence(k: usize, n: usize) -> Style {
    let f = if n > 1 {
        k as f64 / (n - 1) as f64
    } else {
        0.0
    };
    let shade = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    Style::line(plotters::style::RGBColor(
        shade(8, 107),
        shade(48, 174),
        shade(107, 214),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every space and every scheme has its own colour, the same in every call.
    #[test]
    fn every_method_keeps_one_distinct_colour() {
        let mut colours: Vec<_> = crate::space::SPACES
            .iter()
            .map(|e| space(e.name).color)
            .collect();
        colours.extend(crate::time::SCHEMES.iter().map(|e| scheme(e.name, 0).color));
        let distinct = crate::util::unique(colours.iter().map(|c| (c.0, c.1, c.2)));
        assert_eq!(distinct.len(), colours.len().min(PALETTE.len()));
        // The schemes' figures show schemes only: each has a colour of its own there (newmark
        // and hauret_le_tallec were both brown, told apart by a small mark).
        let schemes = &colours[crate::space::SPACES.len()..];
        assert!(schemes.len() <= PALETTE.len());
        assert_eq!(
            crate::util::unique(schemes.iter().map(|c| (c.0, c.1, c.2))).len(),
            schemes.len()
        );
        // Within a registry, no two entries share both colour and mark (newmark and
        // hauret_le_tallec did, PALETTE.len() apart).
        let looks: Vec<String> = crate::time::SCHEMES
            .iter()
            .map(|e| scheme(e.name, 0))
            .map(|s| format!("{:?} {:?}", (s.color.0, s.color.1, s.color.2), s.marker))
            .collect();
        assert_eq!(
            crate::util::unique(looks.iter()).len(),
            looks.len(),
            "{looks:?}"
        );
        assert_eq!(space("mass_redistribution"), space("mass_redistribution"));
        assert_eq!(scheme("newmark", 1).color, scheme("newmark", 0).color);
        assert_ne!(scheme("newmark", 1).dash, scheme("newmark", 0).dash);
    }
}
