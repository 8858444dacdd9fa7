//! A compact f32 model of the hydraulic axis, small enough to run beside the controller on the
//! MCU: 2nd-order spool (100 Hz, 0.7), critically lapped 4-way orifice flow (regularised
//! below 1 bar), compressible chambers with leakage, 200 kg mass, Table 2 LuGre friction with
//! the core's exact step; sub-steps of 100 us (semi-implicit for spool and mass).

use lugre_servo::axis::AxisGeometry;
use lugre_servo::friction::{Conditions, FrictionModel, FrictionState, LugreParams};

const PS: f32 = 210e5;
const PT: f32 = 1e5;
const AXIS: AxisGeometry = AxisGeometry::SIMULATED;
const AA: f32 = AXIS.piston_area_m2() as f32;
const AB: f32 = AXIS.annulus_area_m2() as f32;
const STROKE: f32 = AXIS.stroke_m as f32;
const V0: f32 = 5e-5;
const BETA: f32 = 1.4e9;
const LEAK: f32 = 2e-13;
const MASS: f32 = AXIS.moving_mass_kg as f32;
const KQ: f32 = 3.563_483e-7; // 40 L/min at 35 bar per land
const WV: f32 = 628.318_5;

fn orifice(dp: f32) -> f32 {
    dp / libm::sqrtf(libm::sqrtf(dp * dp + 1e10))
}

/// Plant state.
pub struct Plant {
    pub x: f32,
    pub v: f32,
    pub pa: f32,
    pub pb: f32,
    spool: f32,
    spool_rate: f32,
    friction: FrictionState<f32>,
    model: FrictionModel<f32>,
}

impl Plant {
    pub fn new(x: f32) -> Self {
        let pa = PS * AB / (AA + AB);
        Self {
            x,
            v: 0.0,
            pa,
            pb: PS - pa,
            spool: 0.0,
            spool_rate: 0.0,
            friction: FrictionState::default(),
            model: FrictionModel::plain(LugreParams::table2()),
        }
    }

    /// Advances 1 ms with the valve command `u` held.
    pub fn advance(&mut self, u: f32) {
        let u = if u.is_finite() {
            u.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let h = 1e-4;
        let c = Conditions {
            position: 0.0,
            pressure_sum: 0.0,
            temperature: 0.0,
        };
        for _ in 0..10 {
            let acc = WV * WV * (u - self.spool) - 2.0 * 0.7 * WV * self.spool_rate;
            self.spool_rate += acc * h;
            self.spool = (self.spool + self.spool_rate * h).clamp(-1.0, 1.0);
            let f = self.model.step(&mut self.friction, self.v, &c, h);
            let a = (self.pa * AA - self.pb * AB - f) / MASS;
            self.v += a * h;
            self.x += self.v * h;
            let k = KQ * self.spool;
            let (qa, qb) = if self.spool >= 0.0 {
                (k * orifice(PS - self.pa), -k * orifice(self.pb - PT))
            } else {
                (k * orifice(self.pa - PT), -k * orifice(PS - self.pb))
            };
            let xc = self.x.clamp(0.0, STROKE);
            let (va, vb) = (V0 + AA * xc, V0 + AB * (STROKE - xc));
            let ql = LEAK * (self.pa - self.pb);
            self.pa = (self.pa + h * BETA / va * (qa - AA * self.v - ql)).clamp(2e3, 1.3 * PS);
            self.pb = (self.pb + h * BETA / vb * (qb + AB * self.v + ql)).clamp(2e3, 1.3 * PS);
        }
    }
}
