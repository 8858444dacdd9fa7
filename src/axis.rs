//! The geometry of a hydraulic axis, in one place: the simulator's plant, the controller's
//! defaults and the firmware all take their areas, stroke and mass from here.
//!
//! A differential cylinder with bore `D` and rod `d` has the piston-side area
//! `A_a = pi D^2 / 4` and the rod-side (annulus) area `A_b = A_a - pi d^2 / 4`; the actuator
//! force is `p_a A_a - p_b A_b`.

use core::f64::consts::PI;

/// A differential cylinder moving a mass.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisGeometry {
    /// Piston (bore) diameter D \[m\].
    pub bore_m: f64,
    /// Rod diameter d \[m\].
    pub rod_m: f64,
    /// Stroke \[m\]: positions run from 0 to this.
    pub stroke_m: f64,
    /// Moving mass M \[kg\] (piston, rod and load).
    pub moving_mass_kg: f64,
}

impl AxisGeometry {
    /// The simulated axis of the host tools and the demo: 50/28 mm cylinder, 500 mm stroke,
    /// 200 kg.
    pub const SIMULATED: Self = Self {
        bore_m: 0.050,
        rod_m: 0.028,
        stroke_m: 0.5,
        moving_mass_kg: 200.0,
    };

    /// Piston-side area A_a = pi D^2 / 4 [m^2].
    pub const fn piston_area_m2(&self) -> f64 {
        PI * self.bore_m * self.bore_m / 4.0
    }

    /// Rod-side area A_b = A_a - pi d^2 / 4 [m^2].
    pub const fn annulus_area_m2(&self) -> f64 {
        self.piston_area_m2() - PI * self.rod_m * self.rod_m / 4.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn areas_of_the_simulated_cylinder() {
        let g = AxisGeometry::SIMULATED;
        assert!((g.piston_area_m2() - 1.963_495e-3).abs() < 1e-9);
        assert!((g.annulus_area_m2() - 1.347_743e-3).abs() < 1e-9);
    }
}
