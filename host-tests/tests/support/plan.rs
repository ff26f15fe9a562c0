//! Owned plan pools: a plan of `f64` built from a spec into pools of exactly the sizes it
//! needs (the transient work freed after init), for the tests of renumbered plans.

use deform_kernel::plan::{Plan, PlanSizes, PlanSpec, PlanWork};

/// The three pools of a plan.
pub struct Pools {
    pub reals: Vec<f64>,
    pub indices: Vec<u32>,
    pub bytes: Vec<u8>,
}

impl Pools {
    /// A plan of `spec` in new pools of [`Plan::sizes`], and those sizes.
    pub fn build<const D: usize>(
        spec: &PlanSpec<'_, f64, D>,
    ) -> deform_kernel::Result<(Self, PlanSizes)> {
        let ws = Plan::<f64, D>::work_sizes(spec)?;
        let (mut wr, mut wi, mut wb) =
            (vec![0.0; ws.reals], vec![0; ws.indices], vec![0; ws.bytes]);
        let mut work = PlanWork {
            reals: &mut wr,
            indices: &mut wi,
            bytes: &mut wb,
        };
        let sizes = Plan::<f64, D>::sizes(spec, &mut work)?;
        let mut p = Pools {
            reals: vec![0.0; sizes.reals],
            indices: vec![0; sizes.indices],
            bytes: vec![0; sizes.bytes],
        };
        Plan::init(spec, &mut work, &mut p.reals, &mut p.indices, &mut p.bytes)?;
        Ok((p, sizes))
    }

    /// The plan the pools hold.
    pub fn open<const D: usize>(&mut self) -> deform_kernel::Result<Plan<'_, f64, D>> {
        Plan::open(&mut self.reals, &mut self.indices, &mut self.bytes)
    }
}
