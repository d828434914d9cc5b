//! Reproducible pseudo-random numbers for the unit tests: Marsaglia's 32-bit xorshift
//! (shifts 13, 17, 5), which is all a test needs to cover many cases the same way every run.

/// A xorshift32 state (never zero).
pub struct XorShift32(u32);

impl XorShift32 {
    /// The sequence from `seed` (a zero seed is replaced, as zero is xorshift's fixed point).
    pub fn new(seed: u32) -> XorShift32 {
        XorShift32(if seed == 0 { 0x2545_f491 } else { seed })
    }

    /// The next 32 bits.
    pub fn next_u32(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }

    /// The next value in [0, 1].
    pub fn unit(&mut self) -> f32 {
        self.next_u32() as f32 / u32::MAX as f32
    }
}
