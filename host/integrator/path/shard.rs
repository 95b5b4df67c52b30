//! Shards: one run's sample indices cut into disjoint parts that separate processes or machines
//! render, whose checkpoints `vkrt merge` adds into the same bytes as the whole run. Every part
//! draws from the same scrambled sequence with global sample numbers (Keller and Grünschloß
//! 2012, "Parallel quasi-Monte Carlo integration by partitioning low discrepancy sequences"):
//! part i of n takes the indices floor(i T / n) .. floor((i + 1) T / n) of a run of T samples
//! per pixel. The sums are fixed-point (`super::accumulation`), so adding the parts in any
//! order is exact.

use anyhow::{bail, Result};

/// Part `index` of `count` of a run of `total_spp` samples per pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
    pub total_spp: u64,
}

impl Shard {
    /// Fails unless `index < count` and every part gets at least one sample.
    pub fn new(index: u32, count: u32, total_spp: u64) -> Result<Self> {
        if count == 0 {
            bail!("a run cannot be cut into 0 shards");
        }
        if index >= count {
            bail!("shard {index} of {count} does not exist: shards are numbered 0 to {}", count - 1);
        }
        if total_spp < u64::from(count) {
            bail!("{total_spp} spp cannot be cut into {count} shards of at least one sample each");
        }
        Ok(Self { index, count, total_spp })
    }

    /// The first sample index of part `i`.
    fn start(&self, i: u32) -> u64 {
        (u128::from(i) * u128::from(self.total_spp) / u128::from(self.count)) as u64
    }

    /// This part's first sample index and its number of samples.
    pub fn range(&self) -> (u64, u64) {
        let first = self.start(self.index);
        (first, self.start(self.index + 1) - first)
    }

    /// `I/N`, as `--shard` reads it.
    pub fn label(&self) -> String {
        format!("{}/{}", self.index, self.count)
    }
}

/// The parts a checkpoint holds: some of the `count` parts of one run of `total_spp`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardSet {
    pub count: u32,
    pub total_spp: u64,
    /// The indices held, ascending, without repeats.
    pub indices: Vec<u32>,
}

impl ShardSet {
    pub fn of(shard: Shard) -> Self {
        Self { count: shard.count, total_spp: shard.total_spp, indices: vec![shard.index] }
    }

    /// The union of two sets of one run's parts; fails if they are of different runs (count or
    /// total) or share a part.
    pub fn union(&self, other: &ShardSet) -> Result<ShardSet> {
        if (self.count, self.total_spp) != (other.count, other.total_spp) {
            bail!(
                "shards of different runs: one is cut into {} parts of a {}-spp run, the other into {} of {} spp",
                self.count,
                self.total_spp,
                other.count,
                other.total_spp
            );
        }
        if let Some(i) = other.indices.iter().find(|i| self.indices.contains(i)) {
            bail!("shard {i}/{} is there twice: merging would count its samples twice", self.count);
        }
        let mut indices: Vec<u32> = self.indices.iter().chain(&other.indices).copied().collect();
        indices.sort_unstable();
        Ok(ShardSet { indices, ..*self })
    }

    /// The parts not held.
    pub fn missing(&self) -> Vec<u32> {
        (0..self.count).filter(|i| !self.indices.contains(i)).collect()
    }

    /// A one-line account of what is missing, e.g. "shards 2, 5 of 8 are missing".
    pub fn missing_message(&self) -> Option<String> {
        let missing = self.missing();
        if missing.is_empty() {
            return None;
        }
        let list: Vec<String> = missing.iter().map(u32::to_string).collect();
        let noun = if missing.len() == 1 { "shard" } else { "shards" };
        let verb = if missing.len() == 1 { "is" } else { "are" };
        Some(format!("{noun} {} of {} {verb} missing (numbered from 0)", list.join(", "), self.count))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_cover_the_run_once_for_any_split() {
        for total in [1u64, 7, 16, 17, 1000] {
            for count in 1..=total.min(9) as u32 {
                let mut next = 0;
                for index in 0..count {
                    let (first, n) = Shard::new(index, count, total).unwrap().range();
                    assert_eq!(first, next, "total {total}, {index}/{count}");
                    assert!(n >= 1);
                    next = first + n;
                }
                assert_eq!(next, total);
            }
        }
    }

    #[test]
    fn bad_shards_and_sets_are_refused_or_reported() {
        assert!(Shard::new(3, 3, 10).is_err());
        assert!(Shard::new(0, 0, 10).is_err());
        assert!(Shard::new(0, 4, 3).is_err());
        let a = ShardSet::of(Shard::new(0, 4, 16).unwrap());
        let b = ShardSet::of(Shard::new(2, 4, 16).unwrap());
        let ab = a.union(&b).unwrap();
        assert_eq!(ab.missing(), vec![1, 3]);
        assert_eq!(ab.missing_message().unwrap(), "shards 1, 3 of 4 are missing (numbered from 0)");
        assert!(ab.union(&a).is_err(), "a shard twice");
        assert!(a.union(&ShardSet::of(Shard::new(1, 4, 17).unwrap())).is_err(), "another run's shard");
    }
}
