//! The Stribeck decay along one record, kept for the models that share it.
//!
//! A refit moves the levels, never the curve's shape, and every refit of a search over the
//! stiffness sigma0 or over an effect's own parameter starts from the same Stribeck velocity:
//! each of them evaluated `exp(-(|v|/vs)^delta)` (an `exp`, and a `powf` with a shape, per
//! sample) for the same numbers again, 7 % of a diagnosis's CPU time (perf, session 111). A
//! [`DecayCache`] keeps the last few decays of one record, keyed by everything the decay reads
//! ([`DecayKey`]), and hands out the one it has: the same numbers, bit for bit, as evaluating
//! it again.

use super::inverse::{AxisModel, Prepared};
use std::sync::{Arc, Mutex};

/// Decays kept: a search over the Stribeck velocity evaluates nine at once, and the searches
/// around it come back to the one they started from (about 0.5 MB each on a 60 s record).
const KEPT: usize = 16;

/// What the Stribeck decay `FrictionModel::stribeck_decay_at` reads of a model, as bits (two
/// models with equal keys have the same decay at every sample, bit for bit): the Stribeck
/// velocity, the curve's shape, the temperature dependence's Stribeck velocity factor
/// `exp(q k_v (T - T_ref))` (and `T_ref`, the temperature a record without one is read at),
/// and the asymmetry's Stribeck velocity ratio. `the_decay_reads_nothing_outside_its_key`
/// fails when the decay reads anything else, or a part of the key stops mattering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DecayKey {
    stribeck_velocity: u64,
    shape: Option<[u64; 3]>,
    temperature: Option<[u64; 3]>,
    stribeck_velocity_ratio: Option<u64>,
}

impl DecayKey {
    /// The key of `m`'s decay.
    pub fn of(m: &AxisModel) -> Self {
        let f = &m.friction;
        let e = &f.effects;
        Self {
            stribeck_velocity: f.params.stribeck_velocity().to_bits(),
            shape: e
                .stribeck_shape
                .map(|s| [s.exponent, s.tail_share, s.tail_scale].map(f64::to_bits)),
            temperature: e.temperature_dependence.map(|t| {
                [
                    t.viscous_per_kelvin,
                    t.reference_temperature,
                    t.stribeck_hersey_exponent,
                ]
                .map(f64::to_bits)
            }),
            stribeck_velocity_ratio: e.asymmetry.map(|a| a.stribeck_velocity_ratio.to_bits()),
        }
    }
}

/// The decays of one record ([`AxisModel::stribeck_decay`]) most recently asked for. It
/// borrows the record, so the record cannot change while it lives; asked about another record,
/// it evaluates the decay without keeping it.
pub struct DecayCache<'p> {
    p: &'p Prepared,
    kept: Mutex<Vec<(DecayKey, Arc<[f64]>)>>,
}

impl<'p> DecayCache<'p> {
    /// An empty cache for record `p`.
    pub fn new(p: &'p Prepared) -> Self {
        Self {
            p,
            kept: Mutex::new(Vec::new()),
        }
    }

    /// `m.stribeck_decay(p)`: the kept one where a model with the same key asked before.
    pub fn decay(&self, m: &AxisModel, p: &Prepared) -> Arc<[f64]> {
        if !std::ptr::eq(self.p, p) {
            return m.stribeck_decay(p).into();
        }
        let key = DecayKey::of(m);
        let found = |kept: &[(DecayKey, Arc<[f64]>)]| {
            kept.iter().find(|(k, _)| *k == key).map(|(_, d)| d.clone())
        };
        // a poisoned lock (a panic elsewhere) only costs the evaluation
        if let Some(d) = self.kept.lock().ok().and_then(|k| found(&k)) {
            return d;
        }
        // evaluated outside the lock: two threads may both evaluate one key, never wait
        let d: Arc<[f64]> = m.stribeck_decay(p).into();
        if let Ok(mut kept) = self.kept.lock() {
            if found(&kept).is_none() {
                if kept.len() == KEPT {
                    kept.remove(0);
                }
                kept.push((key, d.clone()));
            }
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::inverse::Protocol;
    use crate::record::Record;
    use lugre_servo::friction::{effects as fx, FrictionModel, LugreParams};

    /// A record whose velocities cross the Stribeck range both ways, with a temperature.
    fn record(scale: f64) -> Prepared {
        let mut text = String::from("t,x,force,temp\n");
        for i in 0..3000 {
            let t = i as f64 * 1e-3;
            let x = scale * 0.01 * (std::f64::consts::TAU * 0.7 * t).sin();
            let force = 200.0 * (std::f64::consts::TAU * 0.7 * t).cos();
            let temp = 30.0 + 5.0 * t;
            text.push_str(&format!("{t:.3},{x:.7},{force:.4},{temp:.3}\n"));
        }
        let rec = Record::parse(&text, std::path::Path::new("r.csv")).unwrap();
        Prepared::new(&rec, "r.csv", Protocol::default()).unwrap()
    }

    fn model() -> AxisModel {
        let params = LugreParams::new(1e7, 300.0, 800.0, 100.0, 150.0, 0.004).unwrap();
        let mut effects = fx::Effects::<f64>::none();
        effects.asymmetry = Some(fx::Asymmetry {
            coulomb_ratio: 0.1,
            static_ratio: -0.05,
            viscous_ratio: 0.2,
            stribeck_velocity_ratio: 0.15,
        });
        effects.stribeck_shape = Some(fx::StribeckShape {
            exponent: 1.4,
            tail_share: 0.3,
            tail_scale: 5.0,
        });
        effects.temperature_dependence = Some(fx::TemperatureDependence {
            viscous_per_kelvin: 0.02,
            coulomb_per_kelvin: -0.003,
            reference_temperature: 31.0,
            stribeck_hersey_exponent: 0.5,
        });
        effects.offset = Some(fx::Offset { force: 3.0 });
        let mut friction = FrictionModel::plain(params);
        friction.effects = effects;
        AxisModel {
            mass_kg: 50.0,
            friction,
        }
    }

    /// [`model`]'s Stribeck shape, temperature dependence and asymmetry, to change a part of.
    fn shape_of(m: &mut AxisModel) -> &mut fx::StribeckShape<f64> {
        m.friction
            .effects
            .stribeck_shape
            .as_mut()
            .expect("model() has one")
    }

    fn temperature_of(m: &mut AxisModel) -> &mut fx::TemperatureDependence<f64> {
        (m.friction.effects.temperature_dependence.as_mut()).expect("model() has one")
    }

    fn asymmetry_of(m: &mut AxisModel) -> &mut fx::Asymmetry<f64> {
        m.friction
            .effects
            .asymmetry
            .as_mut()
            .expect("model() has one")
    }

    /// `m` with `change` made.
    fn changed(m: AxisModel, change: fn(&mut AxisModel)) -> AxisModel {
        let mut changed = m;
        change(&mut changed);
        changed
    }

    /// The effects [`model`] lacks, added: viscous power, load, position and dwell.
    fn with_every_other_effect(m: &mut AxisModel) {
        let e = &mut m.friction.effects;
        e.viscous_power = Some(fx::ViscousPower {
            exponent: 1.5,
            reference_velocity: 0.02,
        });
        e.load_dependence = Some(fx::LoadDependence::power(2e-6, 1e7, 1.0));
        e.position_dependence = Some(fx::PositionDependence::linear(300.0, 0.0));
        let rule = crate::diagnose::fit::DWELL_RULES[0];
        e.dwell_stiction = Some(fx::DwellStiction {
            max_increase: 40.0,
            time_constant: 0.5,
            stick_velocity: rule.stick_velocity(),
            renewal_distance: 1e-4,
            age_at_stick: rule.age,
            clock: rule.clock,
            growth: rule.growth,
        });
    }

    fn bits(d: &[f64]) -> Vec<u64> {
        d.iter().map(|v| v.to_bits()).collect()
    }

    /// A model that differs only outside the key (in its levels, mass, bristle, the asymmetry's
    /// level ratios, the temperature's Coulomb factor, or any other effect) has the same decay
    /// bit for bit, so that the cache may hand it over; each part of the key moves it.
    #[test]
    fn the_decay_reads_nothing_outside_its_key() {
        let p = record(1.0);
        let m = model();
        let same = bits(&m.stribeck_decay(&p));
        let outside: [fn(&mut AxisModel); 7] = [
            |m| m.friction.params = m.friction.params.with_levels(900.0, 120.0, 170.0).unwrap(),
            |m| m.mass_kg = 80.0,
            |m| {
                m.friction.params = LugreParams::new(4e7, 900.0, 800.0, 100.0, 150.0, 4e-3).unwrap()
            },
            |m| {
                let a = asymmetry_of(m);
                (a.coulomb_ratio, a.static_ratio, a.viscous_ratio) = (-0.2, 0.1, -0.3);
            },
            |m| temperature_of(m).coulomb_per_kelvin = 0.01,
            |m| m.friction.effects.offset = None,
            with_every_other_effect,
        ];
        let outside = outside.map(|change| changed(m, change));
        for o in &outside {
            assert_eq!(DecayKey::of(o), DecayKey::of(&m), "{o:?}");
            assert_eq!(bits(&o.stribeck_decay(&p)), same, "{o:?}");
        }
        // every part of the key moves the decay (each a part [`model`] has)
        let inside: [fn(&mut AxisModel); 8] = [
            |m| {
                m.friction.params = LugreParams::new(1e7, 300.0, 800.0, 100.0, 150.0, 5e-3).unwrap()
            },
            |m| shape_of(m).exponent = 1.8,
            |m| shape_of(m).tail_share = 0.4,
            |m| shape_of(m).tail_scale = 3.0,
            |m| temperature_of(m).viscous_per_kelvin = 0.03,
            |m| temperature_of(m).reference_temperature = 25.0,
            |m| temperature_of(m).stribeck_hersey_exponent = 0.8,
            |m| asymmetry_of(m).stribeck_velocity_ratio = -0.1,
        ];
        let inside = inside.map(|change| changed(m, change));
        for i in &inside {
            assert_ne!(DecayKey::of(i), DecayKey::of(&m), "{i:?}");
            assert_ne!(bits(&i.stribeck_decay(&p)), same, "{i:?}");
        }
    }

    /// The cache hands out what evaluating gives, keeps one decay per key, and a cache of one
    /// record asked about another evaluates that record's decay.
    #[test]
    fn a_cached_decay_is_the_evaluated_one_of_its_own_record() {
        let (p, q) = (record(1.0), record(3.0));
        let m = model();
        let cache = DecayCache::new(&p);
        let first = cache.decay(&m, &p);
        assert_eq!(bits(&first), bits(&m.stribeck_decay(&p)));
        let mut levels = m;
        levels.mass_kg = 70.0;
        // the same key: the same buffer, not an evaluation
        assert!(Arc::ptr_eq(&first, &cache.decay(&levels, &p)));
        let other = cache.decay(&m, &q);
        assert_eq!(bits(&other), bits(&m.stribeck_decay(&q)));
        assert_ne!(bits(&other), bits(&first));
        // the other record's decay was not kept: p's is still the one handed out
        assert!(Arc::ptr_eq(&first, &cache.decay(&m, &p)));
        assert_eq!(cache.kept.lock().map(|k| k.len()).unwrap_or(0), 1);
    }
}
