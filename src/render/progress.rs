//! How a render tells its front end how far it has come: the CLI draws a bar, the Python module
//! calls back, the explorer refreshes its preview.

/// What a render's progress counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressUnit {
    /// Tiles of the region finished.
    Tiles,
    /// Milliseconds of the time budget spent.
    BudgetMilliseconds,
}

/// How far a render has come: `done` of `total` units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Advance {
    /// Units done (≤ `total`).
    pub done: u64,
    /// Units in all.
    pub total: u64,
    /// What the units are.
    pub unit: ProgressUnit,
}

/// Receives a render's progress, from any of its worker threads, after each finished tile.
pub trait Progress: Sync {
    /// The render has come this far.
    fn advance(&self, advance: Advance);
}

/// No progress shown.
pub struct Silent;

impl Progress for Silent {
    fn advance(&self, _: Advance) {}
}

/// A function of the advance is a progress receiver.
impl<F: Fn(Advance) + Sync> Progress for F {
    fn advance(&self, advance: Advance) {
        self(advance)
    }
}
