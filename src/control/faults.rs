//! Fault flags. Any input fault puts the valve to its null (safe) command until the inputs have
//! been sane for [`RECOVERY_TICKS`] consecutive periods; observer and refinement faults only
//! degrade the compensation (static model, identified parameters) and clear themselves.

/// Consecutive sane periods before leaving the safe state.
pub const RECOVERY_TICKS: u32 = 50;

/// A set of fault flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Faults(pub u8);

impl Faults {
    /// A measurement or reference was NaN or infinite.
    pub const NON_FINITE: Faults = Faults(1);
    /// The position is outside the stroke (plus margin).
    pub const POSITION_RANGE: Faults = Faults(2);
    /// A chamber pressure is outside the transducer range.
    pub const PRESSURE_RANGE: Faults = Faults(4);
    /// The valve pushed hard for a long time and the encoder did not move.
    pub const STUCK_ENCODER: Faults = Faults(8);
    /// The friction observer diverged and was reset (compensation uses the static model).
    pub const OBSERVER_DIVERGED: Faults = Faults(16);
    /// The online refinement diverged and was reset to the identified parameters.
    pub const REFINEMENT_RESET: Faults = Faults(32);
    /// The reference leaves the axis's stroke, speed or acceleration limits: a setpoint
    /// generator gone wrong must not drive the valve.
    pub const REFERENCE_RANGE: Faults = Faults(64);
    /// Faults that force the safe valve command.
    pub const SAFE_STATE: Faults = Faults(1 | 2 | 4 | 8 | 64);

    /// True if any flag of `other` is set.
    pub fn contains(self, other: Faults) -> bool {
        self.0 & other.0 != 0
    }

    /// Sets the flags of `other`.
    pub fn insert(&mut self, other: Faults) {
        self.0 |= other.0;
    }

    /// No flag set.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}
