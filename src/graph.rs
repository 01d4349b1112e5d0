//! petgraph's visit traits over the engines' own compact tables, so that petgraph's searches
//! (`Dfs`, `Bfs`, `kosaraju_scc`, `depth_first_search`, …) run on them in place instead of on a
//! copy in a `petgraph::Graph`.
//!
//! A table whose nodes are the ids `0..node_bound()` implements [`Successors`] (and
//! [`Predecessors`] where it keeps incoming lists, for `Reversed` and Kosaraju); [`View`] borrows
//! it as a petgraph graph. The successors are listed in the table's own order, so a search
//! visits the nodes in the order a hand-written loop over the table would.

use fixedbitset::FixedBitSet;
use petgraph::visit::{
    GraphBase, GraphRef, IntoNeighbors, IntoNeighborsDirected, IntoNodeIdentifiers, NodeCompactIndexable, NodeCount,
    NodeIndexable, Visitable,
};
use petgraph::Direction;
use std::ops::Range;

/// A directed graph on the nodes `0..node_bound()`, given by its successor lists.
pub trait Successors {
    type Iter<'a>: Iterator<Item = u32>
    where
        Self: 'a;
    fn node_bound(&self) -> usize;
    fn successors(&self, s: u32) -> Self::Iter<'_>;
}

/// A [`Successors`] graph that also lists the sources of the edges into a node.
pub trait Predecessors: Successors {
    type PredIter<'a>: Iterator<Item = u32>
    where
        Self: 'a;
    fn predecessors(&self, s: u32) -> Self::PredIter<'_>;
}

/// A table borrowed as a petgraph graph (nodes `u32`, visit maps `FixedBitSet`).
pub struct View<'a, T>(pub &'a T);

impl<T> Clone for View<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for View<'_, T> {}

impl<T> GraphBase for View<'_, T> {
    type NodeId = u32;
    type EdgeId = (u32, u32);
}

impl<T> GraphRef for View<'_, T> {}

impl<'a, T: Successors> IntoNeighbors for View<'a, T> {
    type Neighbors = T::Iter<'a>;
    fn neighbors(self, a: u32) -> T::Iter<'a> {
        self.0.successors(a)
    }
}

/// The successors or the predecessors of a node.
pub enum Either<A, B> {
    Out(A),
    In(B),
}

impl<A: Iterator<Item = u32>, B: Iterator<Item = u32>> Iterator for Either<A, B> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        match self {
            Either::Out(a) => a.next(),
            Either::In(b) => b.next(),
        }
    }
}

impl<'a, T: Predecessors> IntoNeighborsDirected for View<'a, T> {
    type NeighborsDirected = Either<T::Iter<'a>, T::PredIter<'a>>;
    fn neighbors_directed(self, a: u32, d: Direction) -> Self::NeighborsDirected {
        match d {
            Direction::Outgoing => Either::Out(self.0.successors(a)),
            Direction::Incoming => Either::In(self.0.predecessors(a)),
        }
    }
}

impl<T: Successors> IntoNodeIdentifiers for View<'_, T> {
    type NodeIdentifiers = Range<u32>;
    fn node_identifiers(self) -> Range<u32> {
        0..self.0.node_bound() as u32
    }
}

impl<T: Successors> NodeIndexable for View<'_, T> {
    fn node_bound(&self) -> usize {
        self.0.node_bound()
    }
    fn to_index(&self, a: u32) -> usize {
        a as usize
    }
    fn from_index(&self, i: usize) -> u32 {
        i as u32
    }
}

impl<T: Successors> NodeCount for View<'_, T> {
    fn node_count(&self) -> usize {
        self.0.node_bound()
    }
}

impl<T: Successors> NodeCompactIndexable for View<'_, T> {}

impl<T: Successors> Visitable for View<'_, T> {
    type Map = FixedBitSet;
    fn visit_map(&self) -> FixedBitSet {
        FixedBitSet::with_capacity(self.0.node_bound())
    }
    fn reset_map(&self, map: &mut FixedBitSet) {
        map.clear();
        map.grow(self.0.node_bound());
    }
}

/// A visit map as one flag per node.
pub fn flags(map: &FixedBitSet, n: usize) -> Vec<bool> {
    (0..n).map(|s| map.contains(s)).collect()
}

/// A small graph as successor lists, for searches on a graph built on the spot.
pub struct Lists(pub Vec<Vec<u32>>);

impl Successors for Lists {
    type Iter<'a> = std::iter::Copied<std::slice::Iter<'a, u32>>;
    fn node_bound(&self) -> usize {
        self.0.len()
    }
    fn successors(&self, s: u32) -> Self::Iter<'_> {
        self.0[s as usize].iter().copied()
    }
}
