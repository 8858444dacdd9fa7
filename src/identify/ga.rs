//! A real-coded genetic algorithm on the unit cube `[0, 1]^N`, heap-free (population of `P`
//! individuals in arrays), deterministic for a given random generator, driven ask/tell:
//!
//! ```text
//! let mut ga = Ga::<N, P>::new(config, &mut rng);
//! while !ga.done() {
//!     let costs = evaluate(ga.population());   // the caller: a loop, or rayon on the host
//!     ga.tell(&costs, &mut rng);               // selection, crossover, mutation
//! }
//! ```
//!
//! Common machinery: elitism (the best individual survives unchanged), binary tournament
//! selection, arithmetic crossover `c = l a + (1 - l) b` with `l ~ U(-0.25, 1.25)` (blend
//! crossover, BLX-0.25), genes clamped to the search box. The three strategies differ only in
//! how they set the crossover probability `Pc`, the mutation probability `Pm` and the mutation
//! itself:
//!
//! * **Traditional**: fixed `Pc` and `Pm` (per gene), mutation = uniform reset of the gene.
//! * **Adaptive** (Srinivas and Patnaik 1994) on the cost rank `r` in [0, 1] (0 = best; on raw
//!   or log costs a few outliers push every good individual's probabilities to zero and the
//!   population breeds clones, measured barely better than random search):
//!   `Pc = k1 2 r'` if the better parent is in the better half (`r' <= 1/2`), else 1;
//!   `Pm = k2 2 r` if `r <= 1/2`, else 0.5 (per individual);
//!   mutation = Gaussian on every gene with a non-uniform (decaying) scale
//!   `sigma = 0.1 max(1 - g / m, 0.05)`, as usual for real-coded GAs.
//! * **Improved adaptive** (our reading of the paper's two modules, `k1, k2, gamma, alpha,
//!   beta, m` as in Table 1). The run is a sequence of *cycles*, each an early stage followed
//!   by a late stage; the concentration of the population decides when one ends and the next
//!   begins, and the best individual ever seen is the result:
//!   - *adaptive evolution module* (early stage): every generation measures the population's
//!     concentration `kappa = alpha (1 - D / D0) + beta S` from the gene spread `D` of its
//!     better half (mean per-gene standard deviation; `D0 = 1/sqrt(12)`, that of a uniform
//!     population; the worse half is kept spread by mutation on purpose) and the fitness
//!     concentration `S = c_min / c_avg` (1 when all costs are equal). While
//!     `kappa < alpha (1 - gamma)` the population is still spread: the *exploitation* process
//!     runs the adaptive probabilities above. Once `kappa >= alpha (1 - gamma)` (the better
//!     half within a tenth of the uniform spread; sooner if the costs agree too), or after
//!     `m / 4` generations at the latest, the population has gathered around one basin and
//!     the late stage begins.
//!   - *optimal-solution accuracy module* (late stage): the search box shrinks around the
//!     cycle's best individual `b`, per gene: half-width `w_k = clamp(2.5 rms_k, 1e-15,
//!     gamma)`, recomputed every generation, where `rms_k` is the root-mean-square of
//!     `x_k - b_k` over the better half of the population. Genes the cost is sensitive to
//!     gather near `b` and their box shrinks geometrically; genes it barely sees keep a wide
//!     box (the dynamic LuGre objective is ill-conditioned by ~1e8 between sigma0 and
//!     sigma1). Half the offspring are `b + N(0, (w_k/2)^2)`; the other half are
//!     `b + t (x_i - x_j)`, `t ~ N(0, 1)`, with `x_i, x_j` drawn from the better half, so
//!     steps follow the shape of a correlated valley (the static stage's Fc, Fs - Fc and vs
//!     are strongly correlated); all clamped to the box.
//!   - When the late stage stops improving (10 generations without a better cycle best: the
//!     box has reached the cost's numerical resolution, or a local minimum), the
//!     *diversification* process starts a new cycle from a fresh uniform population, so the
//!     remaining budget searches for a better basin instead of polishing digits that are gone.
//!   - *Hand-over* (ours, not the paper's): on the generation a late stage begins
//!     ([`Ga::late_stage_began`]) the driver runs a Nelder-Mead simplex
//!     ([`super::simplex::polish`]) from the best individual, start steps = the population's
//!     RMS distance from it per gene ([`Ga::spread_about_best`]), at most
//!     [`HANDOVER_BUDGET_PER_GENE`] x N evaluations, and offers its result back
//!     ([`Ga::offer`]); the late stage then goes on around the better of the two and, if it
//!     stalls, diversifies as above. On a gathered, unimodal basin a simplex gains more per
//!     evaluation than 40 individuals a generation (measured: median evaluations to get all
//!     six Table 2 parameters within 1 %, 20 seeds, 2 080 -> 1 029; CMA-ES 1 163); the GA's
//!     cycles keep what the simplex lacks, a way out of a wrong basin (3 of 20 seeds).

use rand_core::RngCore;

/// Which strategy drives the probabilities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Strategy {
    /// Fixed crossover and mutation probabilities.
    Traditional,
    /// Srinivas-Patnaik adaptive probabilities.
    Adaptive,
    /// Adaptive evolution module plus optimal-solution accuracy module.
    Improved,
}

/// GA settings (defaults: Table 1 of the paper).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaConfig {
    /// Strategy.
    pub strategy: Strategy,
    /// Traditional: crossover probability per pair.
    pub crossover_probability: f64,
    /// Traditional: mutation probability per gene.
    pub mutation_probability: f64,
    /// Crossover coefficient k1.
    pub k1: f64,
    /// Mutation coefficient k2.
    pub k2: f64,
    /// Starting coefficient gamma.
    pub gamma: f64,
    /// Starting coefficient alpha.
    pub alpha: f64,
    /// Constant beta.
    pub beta: f64,
    /// Number of generations m.
    pub generations: usize,
}

impl GaConfig {
    /// Table 1 settings with the given strategy.
    pub const fn table1(strategy: Strategy) -> Self {
        Self {
            strategy,
            crossover_probability: 0.8,
            mutation_probability: 0.05,
            k1: 0.8,
            k2: 0.7,
            gamma: 0.1,
            alpha: 0.6,
            beta: 0.4,
            generations: 500,
        }
    }
}

/// Which process the improved strategy ran last (for tests and reports).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Process {
    /// Adaptive probabilities, exploiting.
    Exploit,
    /// Late stage exhausted (no better individual for 10 generations): a new cycle starts
    /// from a fresh uniform population.
    Diversify,
    /// Late stage: search range shrunk around the best.
    Refine,
}

/// The genetic algorithm state: `P` individuals of `N` genes.
#[derive(Clone, Debug)]
pub struct Ga<const N: usize, const P: usize> {
    config: GaConfig,
    pop: [[f64; N]; P],
    generation: usize,
    best: [f64; N],
    best_cost: f64,
    // the current cycle (improved strategy; the whole run for the others)
    cycle_best: [f64; N],
    cycle_cost: f64,
    cycle_start: usize,
    stall: usize,
    refining: bool,
    width: [f64; N],
    last_process: Process,
    late_stage_began: bool,
}

/// Uniform in [0, 1).
fn uniform<R: RngCore>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Standard normal (Box-Muller).
fn normal<R: RngCore>(rng: &mut R) -> f64 {
    let u1 = uniform(rng).max(1e-300);
    let u2 = uniform(rng);
    libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(2.0 * core::f64::consts::PI * u2)
}

fn below<R: RngCore>(rng: &mut R, n: usize) -> usize {
    ((uniform(rng) * n as f64) as usize).min(n.saturating_sub(1))
}

impl<const N: usize, const P: usize> Ga<N, P> {
    /// A uniformly random first population.
    pub fn new<R: RngCore>(config: GaConfig, rng: &mut R) -> Self {
        let mut pop = [[0.0; N]; P];
        for ind in pop.iter_mut() {
            for g in ind.iter_mut() {
                *g = uniform(rng);
            }
        }
        Self {
            config,
            best: pop[0],
            cycle_best: pop[0],
            pop,
            generation: 0,
            best_cost: f64::INFINITY,
            cycle_cost: f64::INFINITY,
            cycle_start: 0,
            stall: 0,
            refining: false,
            width: [config.gamma; N],
            last_process: Process::Exploit,
            late_stage_began: false,
        }
    }

    /// The individuals to evaluate (genes in [0, 1]).
    pub fn population(&self) -> &[[f64; N]; P] {
        &self.pop
    }

    /// Generations completed.
    pub fn generation(&self) -> usize {
        self.generation
    }

    /// True after `m` generations.
    pub fn done(&self) -> bool {
        self.generation >= self.config.generations
    }

    /// Best individual seen so far and its cost.
    pub fn best(&self) -> (&[f64; N], f64) {
        (&self.best, self.best_cost)
    }

    /// The process the improved strategy chose last.
    pub fn last_process(&self) -> Process {
        self.last_process
    }

    /// True on the generation the late stage began (the population has just gathered): the
    /// moment the improved strategy hands over to the simplex (see the module docs).
    pub fn late_stage_began(&self) -> bool {
        self.late_stage_began
    }

    /// Root-mean-square distance of the current population from the best individual, per
    /// gene: the simplex's start steps at a hand-over.
    pub fn spread_about_best(&self) -> [f64; N] {
        let mut s = [0.0; N];
        for ind in &self.pop {
            for k in 0..N {
                s[k] += (ind[k] - self.best[k]) * (ind[k] - self.best[k]);
            }
        }
        s.map(|v| libm::sqrt(v / P as f64).max(1e-9))
    }

    /// Offers a point found outside the GA (the simplex's): it becomes the best individual,
    /// and the current cycle's best the late stage centres on, if it is better.
    pub fn offer(&mut self, genes: &[f64; N], cost: f64) {
        if cost < self.best_cost {
            self.best = *genes;
            self.best_cost = cost;
        }
        if cost < self.cycle_cost {
            self.cycle_best = *genes;
            self.cycle_cost = cost;
        }
    }

    /// Takes the costs of [`Self::population`] (lower is better; NaN counts as worst) and
    /// breeds the next generation.
    pub fn tell<R: RngCore>(&mut self, costs: &[f64; P], rng: &mut R) {
        let mut c = [0.0; P];
        for i in 0..P {
            c[i] = if costs[i].is_nan() {
                f64::MAX
            } else {
                costs[i]
            };
        }
        let mut ib = 0;
        for i in 1..P {
            if c[i] < c[ib] {
                ib = i;
            }
        }
        if c[ib] < self.best_cost {
            self.best_cost = c[ib];
            self.best = self.pop[ib];
        }
        let mut moved = [0.0; N];
        if c[ib] < self.cycle_cost {
            for ((mk, x), b) in moved.iter_mut().zip(&self.pop[ib]).zip(&self.cycle_best) {
                *mk = (x - b).abs();
            }
            self.cycle_cost = c[ib];
            self.cycle_best = self.pop[ib];
            self.stall = 0;
        } else {
            self.stall += 1;
        }

        // rank of each individual (0 = best): the Srinivas-Patnaik rule on ranks, so a few
        // outlying costs cannot push every good individual's probabilities to zero
        let mut order = [0usize; P];
        for (i, o) in order.iter_mut().enumerate() {
            *o = i;
        }
        order.sort_unstable_by(|&a, &b| c[a].total_cmp(&c[b]));
        let mut rank = [0.0f64; P];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r as f64 / (P.max(2) - 1) as f64;
        }

        let g = self.generation as f64;
        let m = self.config.generations.max(2) as f64;
        let process = match self.config.strategy {
            Strategy::Improved => self.choose_process(&c, &order, &moved),
            _ => Process::Exploit,
        };
        self.late_stage_began = process == Process::Refine && self.last_process != Process::Refine;
        self.last_process = process;
        if process == Process::Diversify {
            for ind in self.pop.iter_mut() {
                for gk in ind.iter_mut() {
                    *gk = uniform(rng);
                }
            }
            self.generation += 1;
            return;
        }
        let refine = process == Process::Refine;
        let w = self.width;
        let (lo, hi) = if refine {
            let mut lo = [0.0; N];
            let mut hi = [1.0; N];
            for k in 0..N {
                lo[k] = (self.cycle_best[k] - w[k]).max(0.0);
                hi[k] = (self.cycle_best[k] + w[k]).min(1.0);
            }
            (lo, hi)
        } else {
            ([0.0; N], [1.0; N])
        };

        let adapt = |x: f64, high: f64, k: f64| if x <= 0.5 { k * 2.0 * x } else { high };
        let mut next = [[0.0; N]; P];
        next[0] = self.cycle_best;
        let mut i = 1;
        while i < P {
            let a = self.tournament(&c, rng);
            let b = self.tournament(&c, rng);
            let (mut x, mut y) = (self.pop[a], self.pop[b]);
            if refine {
                if i % 2 == 1 {
                    // half of the late-stage offspring: Gaussian around the cycle's best
                    for k in 0..N {
                        x[k] = self.cycle_best[k] + 0.5 * w[k] * normal(rng);
                    }
                } else {
                    // the other half: the best plus a scaled difference of two of the better
                    // half, so steps follow the shape of a correlated valley
                    let half = (P / 2).max(1);
                    let (ea, eb) = (order[below(rng, half)], order[below(rng, half)]);
                    let t = normal(rng);
                    let (pa, pb) = (&self.pop[ea], &self.pop[eb]);
                    for (k, xk) in x.iter_mut().enumerate() {
                        *xk = self.cycle_best[k] + t * (pa[k] - pb[k]);
                    }
                }
                next[i] = clamp(&x, &lo, &hi);
                i += 1;
                continue;
            }
            let pc = match self.config.strategy {
                Strategy::Traditional => self.config.crossover_probability,
                _ => adapt(rank[a].min(rank[b]), 1.0, self.config.k1),
            };
            if uniform(rng) < pc {
                for k in 0..N {
                    let t = -0.25 + 1.5 * uniform(rng);
                    let (u, v) = (x[k], y[k]);
                    x[k] = t * u + (1.0 - t) * v;
                    y[k] = t * v + (1.0 - t) * u;
                }
            }
            for (child, parent) in [(&mut x, a), (&mut y, b)] {
                match self.config.strategy {
                    Strategy::Traditional => {
                        for gk in child.iter_mut() {
                            if uniform(rng) < self.config.mutation_probability {
                                *gk = uniform(rng);
                            }
                        }
                    }
                    _ => {
                        if uniform(rng) < adapt(rank[parent], 0.5, self.config.k2) {
                            let sigma = 0.1 * (1.0 - g / m).max(0.05);
                            for gk in child.iter_mut() {
                                *gk += sigma * normal(rng);
                            }
                        }
                    }
                }
            }
            next[i] = clamp(&x, &lo, &hi);
            i += 1;
            if i < P {
                next[i] = clamp(&y, &lo, &hi);
                i += 1;
            }
        }
        self.pop = next;
        self.generation += 1;
    }

    /// The improved strategy's decision for the next generation (see the module docs), with
    /// the late stage's box widths updated from the population just evaluated.
    fn choose_process(&mut self, c: &[f64; P], order: &[usize; P], moved: &[f64; N]) -> Process {
        const STALL_GENERATIONS: usize = 10;
        const MIN_WIDTH: f64 = 1e-15;
        // per-gene rms distance of the better half from the cycle's best
        let mut rms = [0.0; N];
        let half = (P / 2).max(1);
        for &i in order.iter().take(half) {
            for ((r, x), b) in rms.iter_mut().zip(&self.pop[i]).zip(&self.cycle_best) {
                *r += (x - b) * (x - b);
            }
        }
        for r in rms.iter_mut() {
            *r = libm::sqrt(*r / half as f64);
        }
        let gamma = self.config.gamma;
        if self.refining {
            if self.stall >= STALL_GENERATIONS {
                // this basin is exhausted: new cycle from a fresh population
                self.refining = false;
                self.cycle_cost = f64::INFINITY;
                self.cycle_start = self.generation + 1;
                self.stall = 0;
                return Process::Diversify;
            }
            for k in 0..N {
                // a best that keeps moving (along a valley) keeps its box open
                self.width[k] = (2.5 * rms[k]).max(3.0 * moved[k]).clamp(MIN_WIDTH, gamma);
            }
            return Process::Refine;
        }
        let d0 = 1.0 / libm::sqrt(12.0);
        let kappa = self.config.alpha * (1.0 - self.spread(&order[..half]) / d0).max(0.0)
            + self.config.beta * self.fitness_concentration(c);
        let explored = self.generation + 1 - self.cycle_start;
        if kappa >= self.config.alpha * (1.0 - gamma) || explored >= self.config.generations / 4 {
            self.refining = true;
            self.stall = 0;
            for (w, r) in self.width.iter_mut().zip(&rms) {
                *w = (2.5 * r).clamp(MIN_WIDTH, gamma);
            }
            Process::Refine
        } else {
            Process::Exploit
        }
    }

    /// `c_min / c_avg` over the finite costs (1 when all are equal, 0 when none is finite).
    fn fitness_concentration(&self, c: &[f64; P]) -> f64 {
        let (mut sum, mut n, mut min) = (0.0, 0usize, f64::INFINITY);
        for &x in c.iter().filter(|x| x.is_finite() && **x < f64::MAX) {
            sum += x;
            n += 1;
            min = min.min(x);
        }
        if n == 0 || sum <= 0.0 {
            return if n == 0 { 0.0 } else { 1.0 };
        }
        (min / (sum / n as f64)).clamp(0.0, 1.0)
    }

    fn tournament<R: RngCore>(&self, c: &[f64; P], rng: &mut R) -> usize {
        let a = below(rng, P);
        let b = below(rng, P);
        if c[a] <= c[b] {
            a
        } else {
            b
        }
    }

    /// Mean per-gene standard deviation of the individuals `members`.
    fn spread(&self, members: &[usize]) -> f64 {
        let n = members.len().max(1) as f64;
        let mut total = 0.0;
        for k in 0..N {
            let mean = members.iter().map(|&i| self.pop[i][k]).sum::<f64>() / n;
            let var = members
                .iter()
                .map(|&i| (self.pop[i][k] - mean) * (self.pop[i][k] - mean))
                .sum::<f64>()
                / n;
            total += libm::sqrt(var);
        }
        total / N.max(1) as f64
    }
}

fn clamp<const N: usize>(x: &[f64; N], lo: &[f64; N], hi: &[f64; N]) -> [f64; N] {
    let mut out = *x;
    for k in 0..N {
        let v = if out[k].is_finite() {
            out[k]
        } else {
            0.5 * (lo[k] + hi[k])
        };
        out[k] = v.clamp(lo[k], hi[k]);
    }
    out
}

/// Evaluations the simplex may use at one hand-over, per gene.
pub const HANDOVER_BUDGET_PER_GENE: usize = 500;

/// Runs a GA to completion on a cost function evaluated in a plain loop (the no_std path);
/// the improved strategy hands over to the simplex each time its late stage begins.
pub fn minimize<const N: usize, const P: usize, R: RngCore, F: FnMut(&[f64; N]) -> f64>(
    config: GaConfig,
    rng: &mut R,
    mut cost: F,
) -> ([f64; N], f64) {
    let mut ga = Ga::<N, P>::new(config, rng);
    let mut costs = [0.0; P];
    while !ga.done() {
        for (c, ind) in costs.iter_mut().zip(ga.population().iter()) {
            *c = cost(ind);
        }
        ga.tell(&costs, rng);
        if config.strategy == Strategy::Improved && ga.late_stage_began() {
            let r = super::simplex::polish(
                &mut cost,
                ga.best().0,
                &ga.spread_about_best(),
                HANDOVER_BUDGET_PER_GENE * N,
            );
            ga.offer(&r.best, r.cost);
        }
    }
    let (b, c) = ga.best();
    (*b, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64: a tiny deterministic generator for the tests.
    struct Mix(u64);
    impl RngCore for Mix {
        fn next_u32(&mut self) -> u32 {
            (self.next_u64() >> 32) as u32
        }
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        fn fill_bytes(&mut self, dest: &mut [u8]) {
            for b in dest.iter_mut() {
                *b = self.next_u32() as u8;
            }
        }
        fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), rand_core::Error> {
            self.fill_bytes(dest);
            Ok(())
        }
    }

    const OPT: [f64; 4] = [0.3, 0.71, 0.12, 0.9];

    fn shifted_sphere(x: &[f64; 4]) -> f64 {
        x.iter()
            .zip(OPT.iter())
            .map(|(a, b)| (a - b) * (a - b))
            .sum()
    }

    /// Rosenbrock on [-2, 2]^2 mapped to the unit square: optimum at (0.75, 0.75).
    fn rosen(x: &[f64; 2]) -> f64 {
        let (a, b) = (4.0 * x[0] - 2.0, 4.0 * x[1] - 2.0);
        (1.0 - a) * (1.0 - a) + 100.0 * (b - a * a) * (b - a * a)
    }

    #[test]
    fn every_strategy_finds_the_sphere_optimum() {
        // random search with the same 20 000 evaluations, for scale
        let mut rng = Mix(7);
        let random_best = (0..20_000)
            .map(|_| {
                shifted_sphere(&[
                    uniform(&mut rng),
                    uniform(&mut rng),
                    uniform(&mut rng),
                    uniform(&mut rng),
                ])
            })
            .fold(f64::INFINITY, f64::min);
        // precision differs by design: only the improved strategy refines around the best
        // (measured: traditional and adaptive end within ~0.025 of the optimum per gene)
        for (strategy, tol) in [
            (Strategy::Traditional, 3e-2),
            (Strategy::Adaptive, 3e-2),
            (Strategy::Improved, 1e-5),
        ] {
            let (best, cost) =
                minimize::<4, 40, _, _>(GaConfig::table1(strategy), &mut Mix(7), shifted_sphere);
            assert!(
                cost < 0.1 * random_best,
                "{strategy:?}: cost {cost} vs random search {random_best}"
            );
            for k in 0..4 {
                assert!(
                    (best[k] - OPT[k]).abs() < tol,
                    "{strategy:?}: gene {k} = {}",
                    best[k]
                );
            }
        }
    }

    #[test]
    fn improved_finds_the_rosenbrock_valley_floor() {
        let (best, c) =
            minimize::<2, 40, _, _>(GaConfig::table1(Strategy::Improved), &mut Mix(3), rosen);
        assert!(
            (best[0] - 0.75).abs() < 1e-2 && (best[1] - 0.75).abs() < 1e-2,
            "cost {c}, at {best:?}"
        );
    }

    #[test]
    fn deterministic_for_a_seed_and_different_across_seeds() {
        let run = |seed| {
            minimize::<4, 20, _, _>(
                GaConfig::table1(Strategy::Improved),
                &mut Mix(seed),
                shifted_sphere,
            )
        };
        assert_eq!(run(11), run(11));
        assert_ne!(run(11).0, run(12).0);
    }

    #[test]
    fn a_gathered_population_starts_the_late_stage_and_a_stalled_one_restarts() {
        let mut rng = Mix(5);
        let mut ga = Ga::<4, 20>::new(GaConfig::table1(Strategy::Improved), &mut rng);
        // collapse the population onto one point
        let p = ga.pop[0];
        ga.pop = [p; 20];
        ga.tell(&[1.0; 20], &mut rng);
        assert_eq!(ga.last_process(), Process::Refine);
        // the late-stage box hugs the gathered population: every offspring is close to it
        assert!(ga
            .population()
            .iter()
            .all(|x| x.iter().zip(p.iter()).all(|(a, b)| (a - b).abs() < 1e-9)));
        // ten generations without a better individual: a new cycle from a fresh population
        for _ in 0..9 {
            ga.tell(&[2.0; 20], &mut rng);
            assert_eq!(ga.last_process(), Process::Refine);
        }
        ga.tell(&[2.0; 20], &mut rng);
        assert_eq!(ga.last_process(), Process::Diversify);
        let members: [usize; 20] = core::array::from_fn(|i| i);
        assert!(ga.spread(&members) > 0.2, "spread {}", ga.spread(&members));
        assert_eq!(ga.best(), (&p, 1.0), "the best ever survives the restart");
    }

    /// A quadratic whose second gene matters 1e8 times less than the first, like sigma1 next
    /// to sigma0 in the dynamic LuGre stage: finding the second needs the first to ~1e-5.
    fn ill_conditioned(x: &[f64; 2]) -> f64 {
        (x[0] - 0.3) * (x[0] - 0.3) + 1e-8 * (x[1] - 0.6) * (x[1] - 0.6)
    }

    /// A narrow valley along the diagonal (condition 1e6), like Fc and Fs - Fc (measured:
    /// within 2.4e-6 of the optimum on seed 1; without the box kept open by a moving best,
    /// 0.044).
    fn diagonal_valley(x: &[f64; 2]) -> f64 {
        let (u, v) = (x[0] - x[1], x[0] + x[1] - 1.2);
        1e6 * u * u + v * v
    }

    #[test]
    fn improved_resolves_ill_conditioned_and_correlated_genes() {
        for seed in 1..=5 {
            let (b, c) = minimize::<2, 40, _, _>(
                GaConfig::table1(Strategy::Improved),
                &mut Mix(seed),
                ill_conditioned,
            );
            assert!((b[1] - 0.6).abs() < 1e-3, "seed {seed}: {b:?}, cost {c}");
            let (b, c) = minimize::<2, 40, _, _>(
                GaConfig::table1(Strategy::Improved),
                &mut Mix(seed),
                diagonal_valley,
            );
            assert!(
                (b[0] - 0.6).abs() < 1e-5 && (b[1] - 0.6).abs() < 1e-5,
                "seed {seed}: {b:?}, cost {c}"
            );
        }
    }

    #[test]
    fn nan_costs_lose() {
        let mut rng = Mix(9);
        let mut ga = Ga::<2, 10>::new(GaConfig::table1(Strategy::Adaptive), &mut rng);
        let mut costs = [f64::NAN; 10];
        costs[3] = 1.0;
        let p3 = ga.pop[3];
        ga.tell(&costs, &mut rng);
        assert_eq!(ga.best().0, &p3);
    }
}
