//! The candidate surface sequences of a source, stored as a tree of their common beginnings.
//!
//! Sequence discovery (`path::discover_sequences`) follows rays through the scene, so the
//! sequences it finds form a tree: each is one event longer than its parent. A plate with m
//! internal reflections has O(m) sequences of length O(m); listing each one on its own costs
//! O(m²) to build and to sort, the tree O(m). Tracing walks it depth first so that orders
//! sharing a beginning trace it once (`trace`'s far-field walk).
//!
//! The order of the nodes is depth first, parent before children, children in event order
//! (`Event`'s `Ord`: by surface, reflection before refraction): this is exactly the sorted order
//! of the sequences as lists (a beginning sorts before its extensions).

use crate::trace::path::{Event, EventKind, Sequence};

/// One node of a [`SequenceTree`]: the sequence from the root to here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeNode {
    /// The last event of the node's sequence (`None` at the root, the empty sequence).
    pub event: Option<Event>,
    /// Number of events in the node's sequence.
    pub depth: usize,
    /// Whether the node's sequence is a candidate (the tree also holds beginnings that are not).
    pub candidate: bool,
    /// One past the node's last descendant: its subtree is `nodes[i..subtree_end]`.
    pub subtree_end: usize,
}

/// The candidate sequences of one source as a tree (module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SequenceTree {
    nodes: Vec<TreeNode>,
    /// The most events of any node.
    depth: usize,
}

/// A tree under construction: children found in any order, deduplicated.
#[derive(Clone, Debug, Default)]
pub(crate) struct TreeBuilder {
    /// Node 0 is the root.
    nodes: Vec<BuildNode>,
}

/// A node of a [`TreeBuilder`].
#[derive(Clone, Debug, Default)]
struct BuildNode {
    event: Option<Event>,
    candidate: bool,
    /// (event, node) of each child, in the order found.
    children: Vec<(Event, usize)>,
}

impl TreeBuilder {
    /// A builder holding only the root (the empty sequence).
    pub fn new() -> Self {
        TreeBuilder {
            nodes: vec![BuildNode::default()],
        }
    }

    /// The root (the empty sequence).
    pub(crate) const ROOT: usize = 0;

    /// The child of `node` one `event` further, created if new.
    pub fn child(&mut self, node: usize, event: Event) -> usize {
        let children = &self.nodes[node].children;
        if let Some(&(_, c)) = children.iter().find(|(e, _)| *e == event) {
            return c;
        }
        let c = self.nodes.len();
        self.nodes.push(BuildNode {
            event: Some(event),
            ..BuildNode::default()
        });
        self.nodes[node].children.push((event, c));
        c
    }

    /// Mark `node`'s sequence as a candidate.
    pub(crate) fn mark(&mut self, node: usize) {
        self.nodes[node].candidate = true;
    }

    /// The finished tree, nodes in sorted depth-first order.
    pub fn finish(mut self) -> SequenceTree {
        for n in &mut self.nodes {
            n.children.sort_unstable();
        }
        let mut nodes: Vec<TreeNode> = Vec::with_capacity(self.nodes.len());
        // Iterative pre-order: (builder node, depth); a node's subtree end is known when the
        // walk leaves it, recorded through `open` (indices into `nodes` of unfinished nodes).
        let mut stack = vec![(Self::ROOT, 0usize)];
        let mut open: Vec<usize> = Vec::new();
        while let Some((b, depth)) = stack.pop() {
            while open.last().is_some_and(|&i| nodes[i].depth >= depth) {
                let i = open.pop().unwrap();
                nodes[i].subtree_end = nodes.len();
            }
            let n = &self.nodes[b];
            open.push(nodes.len());
            nodes.push(TreeNode {
                event: n.event,
                depth,
                candidate: n.candidate,
                subtree_end: 0,
            });
            stack.extend(n.children.iter().rev().map(|&(_, c)| (c, depth + 1)));
        }
        for i in open {
            nodes[i].subtree_end = nodes.len();
        }
        let depth = nodes.iter().map(|n| n.depth).max().unwrap_or(0);
        SequenceTree { nodes, depth }
    }
}

impl SequenceTree {
    /// The tree of the given sequences (duplicates are kept once; the order given is lost).
    pub fn from_sequences<I: IntoIterator<Item = Sequence>>(sequences: I) -> Self {
        let mut b = TreeBuilder::new();
        for seq in sequences {
            let node = seq
                .iter()
                .fold(TreeBuilder::ROOT, |node, &ev| b.child(node, ev));
            b.mark(node);
        }
        b.finish()
    }

    /// Every node in depth-first order (module docs); node 0 is the root.
    pub fn nodes(&self) -> &[TreeNode] {
        &self.nodes
    }

    /// Number of candidate sequences.
    pub fn len(&self) -> usize {
        self.nodes.iter().filter(|n| n.candidate).count()
    }

    /// No candidate sequence at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Call `visit` with every candidate sequence in sorted order (O(1) per node: one sequence
    /// buffer, on the stack for trees up to 32 events deep, is overwritten along the walk).
    pub fn for_each(&self, mut visit: impl FnMut(&[Event])) {
        const ON_STACK: usize = 32;
        let depth = self.depth;
        let filler = Event {
            surface: 0,
            kind: EventKind::Reflect,
        };
        let mut stack = [filler; ON_STACK];
        let mut heap = Vec::new();
        let seq: &mut [Event] = if depth <= ON_STACK {
            &mut stack
        } else {
            heap.resize(depth, filler);
            &mut heap
        };
        for n in &self.nodes {
            if let Some(ev) = n.event {
                seq[n.depth - 1] = ev;
            }
            if n.candidate {
                visit(&seq[..n.depth]);
            }
        }
    }

    /// The candidate sequences in sorted order, each as its own list.
    pub fn sequences(&self) -> Vec<Sequence> {
        let mut all = Vec::new();
        self.for_each(|s| all.push(s.to_vec()));
        all
    }
}
