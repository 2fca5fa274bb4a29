//! The dimensions of the efforts and flows of a model's bonds, found by propagation.
//!
//! Each bond has two unknowns, the dimension of its effort and of its flow. Every law the
//! checks use relates two of them by a known factor (a junction: equal; a TF of ratio `n`:
//! `dim(e_in) = dim(n)·dim(e_out)`; an I of inertance `m`: `dim(e) = dim(m)/s·dim(f)`), or
//! fixes one (a source). Dimensions form a group under multiplication, so these are the
//! relations of a weighted union-find: each unknown points at a parent with the factor
//! between them, a class of related unknowns has at most one known dimension (at its root),
//! and a relation that closes a loop, or joins two known classes, either agrees or is a
//! [`Conflict`] that says which factor the law would have needed.
//!
//! # Complexity
//! Each relation costs a walk to two roots. Classes are joined by size (the smaller root
//! under the larger), so no walk is longer than `log2 n` links and a model's whole check is
//! `O(n log n)` in its bonds; `get` stays a read (`&self`), which path compression would not.

use super::dimension::Dim;

/// An unknown: the effort or flow of one bond.
pub type Var = usize;

/// The effort of bond `bond`.
pub fn effort(bond: usize) -> Var {
    2 * bond
}

/// The flow of bond `bond`.
pub fn flow(bond: usize) -> Var {
    2 * bond + 1
}

/// A known dimension and what made it known, for messages.
#[derive(Clone, Debug, PartialEq)]
pub struct Known {
    /// The dimension.
    pub dim: Dim,
    /// What set it: `the effort source 'push'`.
    pub by: String,
}

/// A relation or value that disagrees with what is already known.
#[derive(Clone, Debug, PartialEq)]
pub enum Conflict {
    /// A relation `dim(a) = dim(b)·r` where the rest of the graph already makes the factor
    /// `needed`.
    Factor {
        /// The factor the graph needs.
        needed: Dim,
    },
    /// A value where the unknown is already known otherwise.
    Value(Known),
}

/// The unknowns and what is known of them.
#[derive(Clone, Debug)]
pub struct Solver {
    parent: Vec<Var>,
    /// `dim(v) = dim(parent(v))·offset(v)`.
    offset: Vec<Dim>,
    /// At a root: the class's known dimension, with its provenance.
    value: Vec<Option<Known>>,
    /// At a root: how many unknowns its class holds.
    size: Vec<u32>,
}

impl Solver {
    /// `count` unknowns, all unrelated and unknown.
    pub fn new(count: usize) -> Self {
        Self {
            parent: (0..count).collect(),
            offset: vec![Dim::NONE; count],
            value: vec![None; count],
            size: vec![1; count],
        }
    }

    /// The root of `v`'s class and the factor `dim(v) = dim(root)·factor`.
    fn find(&self, mut v: Var) -> (Var, Dim) {
        let mut factor = Dim::NONE;
        while self.parent[v] != v {
            factor = factor.times(self.offset[v]);
            v = self.parent[v];
        }
        (v, factor)
    }

    /// The dimension of `v`, if known.
    pub fn get(&self, v: Var) -> Option<Dim> {
        let (root, factor) = self.find(v);
        self.value[root].as_ref().map(|k| k.dim.times(factor))
    }

    /// What made `v` known, if it is.
    #[cfg(test)]
    pub fn known(&self, v: Var) -> Option<Known> {
        let (root, factor) = self.find(v);
        self.value[root].as_ref().map(|k| Known {
            dim: k.dim.times(factor),
            by: k.by.clone(),
        })
    }

    /// Relates `dim(a) = dim(b)·r`. Returns whether anything was learnt.
    ///
    /// # Errors
    /// [`Conflict::Factor`] with the factor the rest of the graph makes, if it is not `r`.
    pub fn relate(&mut self, a: Var, b: Var, r: Dim) -> Result<bool, Conflict> {
        let (ra, fa) = self.find(a);
        let (rb, fb) = self.find(b);
        if ra == rb {
            let actual = fa.per(fb);
            return if actual == r {
                Ok(false)
            } else {
                Err(Conflict::Factor { needed: actual })
            };
        }
        if let (Some(va), Some(vb)) = (&self.value[ra], &self.value[rb]) {
            let (da, db) = (va.dim.times(fa), vb.dim.times(fb));
            if da != db.times(r) {
                return Err(Conflict::Factor { needed: da.per(db) });
            }
        }
        // dim(ra) = dim(a)/fa = dim(b)·r/fa = dim(rb)·fb·r/fa.
        let link = fb.times(r).per(fa);
        // The joined class's value, as a value of `rb`: `b`'s class keeps its provenance
        // where both are known.
        let merged = match self.value[rb].take() {
            Some(known) => Some(known),
            None => self.value[ra].take().map(|known| Known {
                dim: known.dim.per(link),
                by: known.by,
            }),
        };
        self.value[ra] = None;
        // The smaller class hangs under the larger one's root.
        if self.size[ra] <= self.size[rb] {
            self.parent[ra] = rb;
            self.offset[ra] = link;
            self.size[rb] += self.size[ra];
            self.value[rb] = merged;
        } else {
            // dim(rb) = dim(ra)/link.
            self.parent[rb] = ra;
            self.offset[rb] = link.recip();
            self.size[ra] += self.size[rb];
            self.value[ra] = merged.map(|known| Known {
                dim: known.dim.times(link),
                by: known.by,
            });
        }
        Ok(true)
    }

    /// Sets `dim(v) = dim`. Returns whether anything was learnt.
    ///
    /// # Errors
    /// [`Conflict::Value`] with what is known of `v`, if it differs.
    pub fn set(&mut self, v: Var, dim: Dim, by: impl Into<String>) -> Result<bool, Conflict> {
        let (root, factor) = self.find(v);
        match &self.value[root] {
            Some(known) if known.dim.times(factor) == dim => Ok(false),
            Some(known) => Err(Conflict::Value(Known {
                dim: known.dim.times(factor),
                by: known.by.clone(),
            })),
            None => {
                self.value[root] = Some(Known {
                    dim: dim.per(factor),
                    by: by.into(),
                });
                Ok(true)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relations_carry_a_value_through_factors_and_catch_a_loop_that_disagrees() {
        let mut solver = Solver::new(4);
        let (m, s) = (Dim::LENGTH, Dim::TIME);
        // x1 = x0·m, x2 = x1·s, then x0 = m/s.
        assert_eq!(solver.relate(1, 0, m), Ok(true));
        assert_eq!(solver.relate(2, 1, s), Ok(true));
        assert_eq!(solver.set(0, m.per(s), "a source"), Ok(true));
        assert_eq!(solver.get(2), Some(m.times(m)));
        assert_eq!(solver.known(2).unwrap().by, "a source");
        // A loop x2 = x0·m is inconsistent: the graph makes x2/x0 = m·s.
        assert_eq!(
            solver.relate(2, 0, m),
            Err(Conflict::Factor { needed: m.times(s) })
        );
        assert_eq!(solver.relate(2, 0, m.times(s)), Ok(false));
        // Setting a known unknown to another value names what set it.
        assert!(
            matches!(solver.set(1, s, "x"), Err(Conflict::Value(k)) if k.dim == m.times(m).per(s))
        );
        // Joining a known class to an unknown one carries the value over.
        assert_eq!(solver.set(3, s, "y"), Ok(true));
        assert_eq!(solver.relate(0, 3, m.per(s.times(s))), Ok(true));
        assert_eq!(solver.get(0), Some(m.per(s)));
    }

    /// The depth of `v` below its root.
    fn depth(solver: &Solver, mut v: Var) -> usize {
        let mut depth = 0;
        while solver.parent[v] != v {
            v = solver.parent[v];
            depth += 1;
        }
        depth
    }

    #[test]
    fn relations_in_any_order_give_every_unknown_its_dimension_in_shallow_classes() {
        // Each unknown's true dimension is m^a s^b with (a, b) drawn by a fixed LCG; every
        // relation states the true ratio, in a scrambled order that joins classes of every
        // size both ways round, and one unknown is set late.
        let n = 4096;
        let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = |modulus: u64| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 33) % modulus
        };
        let truth: Vec<Dim> = (0..n)
            .map(|_| {
                let (a, b) = (next(7) as i32 - 3, next(7) as i32 - 3);
                Dim::LENGTH.powi(a).times(Dim::TIME.powi(b))
            })
            .collect();
        let mut solver = Solver::new(n);
        // A spanning tree: each unknown related to an earlier one, or an earlier one to it.
        for v in 1..n {
            let u = next(v as u64) as usize;
            let (a, b) = if next(2) == 0 { (u, v) } else { (v, u) };
            assert_eq!(solver.relate(a, b, truth[a].per(truth[b])), Ok(true));
            if v == n / 2 {
                assert_eq!(solver.set(u, truth[u], "half way"), Ok(true));
            }
        }
        for (v, dim) in truth.iter().enumerate() {
            assert_eq!(solver.get(v), Some(*dim), "unknown {v}");
            assert!(
                depth(&solver, v) <= 12,
                "unknown {v} is {} deep",
                depth(&solver, v)
            );
        }
        // Closing a loop with the wrong factor names the one the graph makes.
        let wrong = truth[7].per(truth[9]).times(Dim::MASS);
        assert_eq!(
            solver.relate(7, 9, wrong),
            Err(Conflict::Factor {
                needed: truth[7].per(truth[9])
            })
        );
    }
}
