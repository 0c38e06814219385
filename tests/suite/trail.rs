//! `Trail`, the record type that lets a plate's reflected orders share their common beginning,
//! behaves exactly like a `Vec` that is copied on clone: random programs of pushes and clones
//! over a pool of owned and shared trails are run against a pool of `Vec` models.

use crate::common;

use common::config;
use fringe::optics::trail::Trail;
use proptest::prelude::*;

/// One step of a program: push a value onto trail `i`, or clone trail `i` into a new slot.
#[derive(Clone, Debug)]
enum Op {
    Push(usize, u32),
    Clone(usize),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => (0usize..8, any::<u32>()).prop_map(|(i, v)| Op::Push(i, v)),
        1 => (0usize..8).prop_map(Op::Clone),
    ]
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn a_trail_reads_like_its_vec_model(shared in any::<bool>(), ops in prop::collection::vec(op(), 0..200)) {
        let mut trails = vec![if shared { Trail::shared() } else { Trail::new() }];
        let mut models: Vec<Vec<u32>> = vec![Vec::new()];
        // Clones made of each slot: (slot, its clone's slot, length at the clone).
        let mut clones: Vec<(usize, usize, usize)> = Vec::new();
        for op in ops {
            match op {
                Op::Push(i, v) => {
                    let i = i % trails.len();
                    trails[i].push(v);
                    models[i].push(v);
                }
                Op::Clone(i) => {
                    let i = i % trails.len();
                    clones.push((i, trails.len(), models[i].len()));
                    trails.push(trails[i].clone());
                    models.push(models[i].clone());
                }
            }
        }
        for (t, m) in trails.iter().zip(&models) {
            prop_assert_eq!(t.len(), m.len());
            prop_assert_eq!(t.is_empty(), m.is_empty());
            prop_assert_eq!(t.last(), m.last());
            prop_assert_eq!(t.first(), m.first());
            prop_assert_eq!(t.iter().copied().collect::<Vec<_>>(), m.clone());
            prop_assert_eq!(t.to_vec(), m.clone());
            prop_assert_eq!(t.iter().len(), m.len());
            for (k, v) in m.iter().enumerate() {
                prop_assert_eq!(t[k], *v);
            }
            prop_assert_eq!(t.get(m.len()), None);
            prop_assert!(t == m, "Trail == Vec");
            let owned = Trail::from(m.clone());
            prop_assert!(*t == owned, "shared == owned with the same elements");
            prop_assert_eq!(format!("{t:?}"), format!("{m:?}"));
            prop_assert_eq!(t.is_shared(), shared);
        }
        for (a, b) in trails.iter().zip(&models).flat_map(|x| trails.iter().zip(&models).map(move |y| (x, y))) {
            prop_assert_eq!(a.0 == b.0, a.1 == b.1, "equality follows the elements");
        }
        // A clone shares the beginning it was cloned with, when shared, and never when owned.
        for (from, to, len) in clones {
            if len > 0 {
                prop_assert_eq!(trails[from].shares_beginning(&trails[to], len), shared);
            }
        }
    }
}
