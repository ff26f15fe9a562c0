//! NACA 4-digit sections with a closed, sharp trailing edge.
//!
//! Chord 1, leading edge at the origin, trailing edge at `(1, 0)`. Thickness
//! `y_t = 5 t (0.2969 √x − 0.1260 x − 0.3516 x² + 0.2843 x³ − 0.1036 x⁴)` (the closed-TE last
//! coefficient), mean line of the 4-digit series, surface points offset normal to the mean
//! line. Points are clustered toward both edges by cosine spacing.

use crate::{MeshError, Result};

/// A NACA 4-digit section: `m p tt` = maximum camber `m`% chord at `p`/10 chord, thickness
/// `tt`% chord.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Naca4 {
    /// Maximum camber (fraction of chord), e.g. 0.02 for "2412".
    pub max_camber: f64,
    /// Chordwise position of maximum camber (fraction of chord), e.g. 0.4.
    pub camber_position: f64,
    /// Maximum thickness (fraction of chord), e.g. 0.12.
    pub thickness: f64,
}

impl Naca4 {
    /// Parses a 4-digit code such as `"2412"` or `"0012"`.
    pub fn parse(code: &str) -> Result<Self> {
        let digits: Vec<u32> = code.chars().filter_map(|c| c.to_digit(10)).collect();
        if code.len() != 4 || digits.len() != 4 {
            return Err(MeshError::BadNacaCode(code.to_string()));
        }
        let m = digits[0] as f64 / 100.0;
        let p = digits[1] as f64 / 10.0;
        let t = (digits[2] * 10 + digits[3]) as f64 / 100.0;
        if t <= 0.0 || (m > 0.0 && p <= 0.0) {
            return Err(MeshError::BadNacaCode(code.to_string()));
        }
        Ok(Naca4 {
            max_camber: m,
            camber_position: p,
            thickness: t,
        })
    }

    /// Half thickness at chordwise position `x ∈ [0, 1]` (zero at both ends).
    pub fn half_thickness(&self, x: f64) -> f64 {
        let x = x.clamp(0.0, 1.0);
        if x >= 1.0 {
            return 0.0;
        }
        5.0 * self.thickness
            * (0.2969 * libm::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x
                - 0.1036 * x * x * x * x)
    }

    /// Mean line height and slope at `x ∈ [0, 1]`.
    pub fn camber(&self, x: f64) -> (f64, f64) {
        let m = self.max_camber;
        let p = self.camber_position;
        if m == 0.0 {
            return (0.0, 0.0);
        }
        if x < p {
            (
                m / (p * p) * (2.0 * p * x - x * x),
                2.0 * m / (p * p) * (p - x),
            )
        } else {
            let q = (1.0 - p) * (1.0 - p);
            (
                m / q * ((1.0 - 2.0 * p) + 2.0 * p * x - x * x),
                2.0 * m / q * (p - x),
            )
        }
    }

    /// Surface point at chordwise station `x` on the upper (`true`) or lower surface.
    pub fn surface_point(&self, x: f64, upper: bool) -> [f64; 2] {
        if x <= 0.0 {
            return [0.0, 0.0];
        }
        if x >= 1.0 {
            return [1.0, 0.0];
        }
        let yt = self.half_thickness(x);
        let (yc, dyc) = self.camber(x);
        let theta = libm::atan(dyc);
        let (s, c) = (libm::sin(theta), libm::cos(theta));
        if upper {
            [x - yt * s, yc + yt * c]
        } else {
            [x + yt * s, yc - yt * c]
        }
    }

    /// A closed surface loop of `n` points (n even, ≥ 4), **clockwise**: index 0 is the sharp
    /// trailing edge `(1, 0)`, then the lower surface to the leading edge (index `n/2`, the
    /// origin), then the upper surface back toward the trailing edge (not repeated). Stations
    /// `x = (1 + cos(2πk/n)) / 2` cluster points toward both edges.
    pub fn surface(&self, n: usize) -> Result<Vec<[f64; 2]>> {
        if n < 4 || n % 2 != 0 {
            return Err(MeshError::InvalidOption(format!(
                "surface_points must be even and at least 4 (got {n})"
            )));
        }
        let half = n / 2;
        let mut pts = Vec::with_capacity(n);
        for k in 0..n {
            let beta = 2.0 * core::f64::consts::PI * k as f64 / n as f64;
            let x = 0.5 * (1.0 + libm::cos(beta));
            let p = if k == 0 {
                [1.0, 0.0]
            } else if k == half {
                [0.0, 0.0]
            } else {
                self.surface_point(x, k > half)
            };
            pts.push(p);
        }
        Ok(pts)
    }
}
