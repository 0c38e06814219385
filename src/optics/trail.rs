//! `Trail<T>`: the append-only record of a ray's history (its events, points, directions,
//! indices, phase ledger) that can share its beginning with the records of other rays.
//!
//! The reflected orders of a plate leave the source along one zig-zag: order k + 1's history is
//! order k's up to its last bounce, then two more events. Recording each order with its own
//! copy costs O(k) per order and O(m²) for m bounces; a trail that *shares* the common
//! beginning costs O(1) per event, so the whole family costs O(m) (`trace`'s far-field walk).
//!
//! A trail is either
//! * **owned**: a plain `Vec` (what a single traced ray uses; `clone` copies it), or
//! * **shared**: a persistent list of its elements from the last back to the first, each node
//!   behind an `Arc`. `clone` is O(1) (one reference count) and `push` adds one node; trails
//!   cloned from one another share every node they had in common.
//!
//! Both read the same: [`Trail::iter`] visits the elements from the first, `len`, `last`,
//! indexing and equality see only the elements. Indexing a shared trail walks back from the
//! end (O(len − i)); iterate instead where every element is needed.

use std::fmt;
use std::sync::Arc;

/// A persistent list node: an element and everything before it.
struct Node<T> {
    item: T,
    prev: Option<Arc<Node<T>>>,
}

impl<T> Drop for Node<T> {
    /// Free a long list iteratively (the default drop would recurse once per node).
    fn drop(&mut self) {
        let mut next = self.prev.take();
        while let Some(node) = next {
            match Arc::try_unwrap(node) {
                Ok(mut n) => next = n.prev.take(),
                Err(_) => break, // still shared: its other owners keep the rest
            }
        }
    }
}

/// An append-only sequence, owned or sharing its beginning with other trails (module docs).
pub struct Trail<T>(Repr<T>);

enum Repr<T> {
    /// Elements in order, in one buffer.
    Owned(Vec<T>),
    /// The last element's node (`None` when empty) and the number of elements.
    Shared {
        last: Option<Arc<Node<T>>>,
        len: usize,
    },
}

impl<T> Default for Trail<T> {
    fn default() -> Self {
        Trail(Repr::Owned(Vec::new()))
    }
}

impl<T: Clone> Clone for Trail<T> {
    /// O(1) for a shared trail; a copy of the buffer for an owned one.
    fn clone(&self) -> Self {
        Trail(match &self.0 {
            Repr::Owned(v) => Repr::Owned(v.clone()),
            Repr::Shared { last, len } => Repr::Shared {
                last: last.clone(),
                len: *len,
            },
        })
    }
}

impl<T> From<Vec<T>> for Trail<T> {
    #[inline]
    fn from(v: Vec<T>) -> Self {
        Trail(Repr::Owned(v))
    }
}

impl<T> Trail<T> {
    /// An empty owned trail.
    pub fn new() -> Self {
        Trail(Repr::Owned(Vec::new()))
    }

    /// An empty owned trail with room for `capacity` elements.
    #[inline]
    pub(crate) fn with_capacity(capacity: usize) -> Self {
        Trail(Repr::Owned(Vec::with_capacity(capacity)))
    }

    /// An empty shared trail: clones of it and of its extensions share their common elements.
    pub fn shared() -> Self {
        Trail(Repr::Shared { last: None, len: 0 })
    }

    /// A shared trail of one element.
    pub(crate) fn shared_of(item: T) -> Self {
        let mut t = Trail::shared();
        t.push(item);
        t
    }

    /// Whether clones share elements (see the module docs).
    pub fn is_shared(&self) -> bool {
        matches!(self.0, Repr::Shared { .. })
    }

    /// The number of elements.
    #[inline]
    pub fn len(&self) -> usize {
        match &self.0 {
            Repr::Owned(v) => v.len(),
            Repr::Shared { len, .. } => *len,
        }
    }

    /// Whether there are none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Append an element (a new node for a shared trail; its clones do not see it).
    #[inline]
    pub fn push(&mut self, item: T) {
        match &mut self.0 {
            Repr::Owned(v) => v.push(item),
            Repr::Shared { last, len } => {
                *last = Some(Arc::new(Node {
                    item,
                    prev: last.take(),
                }));
                *len += 1;
            }
        }
    }

    /// The last element, O(1).
    #[inline]
    pub fn last(&self) -> Option<&T> {
        match &self.0 {
            Repr::Owned(v) => v.last(),
            Repr::Shared { last, .. } => last.as_deref().map(|n| &n.item),
        }
    }

    /// The first element (O(len) for a shared trail).
    pub fn first(&self) -> Option<&T> {
        self.get(0)
    }

    /// Element `i` from the first (O(len − i) for a shared trail).
    #[inline]
    pub fn get(&self, i: usize) -> Option<&T> {
        match &self.0 {
            Repr::Owned(v) => v.get(i),
            Repr::Shared { .. } => self.node(i).map(|n| &n.item),
        }
    }

    /// Whether the first `n` elements of `self` and `other` are stored once, shared by both
    /// (trails cloned from a common beginning of at least `n` elements); always false for owned
    /// trails when `n > 0`, even if the elements are equal.
    pub fn shares_beginning(&self, other: &Trail<T>, n: usize) -> bool {
        if n == 0 {
            return true;
        }
        match (self.node(n - 1), other.node(n - 1)) {
            (Some(a), Some(b)) => std::ptr::eq(a, b),
            _ => false,
        }
    }

    /// The node holding element `i` of a shared trail.
    fn node(&self, i: usize) -> Option<&Node<T>> {
        let Repr::Shared { last, len } = &self.0 else {
            return None;
        };
        if i >= *len {
            return None;
        }
        let mut node = last.as_deref()?;
        for _ in 0..(*len - 1 - i) {
            node = node.prev.as_deref()?;
        }
        Some(node)
    }

    /// The elements from the first to the last.
    #[inline]
    pub fn iter(&self) -> Iter<'_, T> {
        match &self.0 {
            Repr::Owned(v) => Iter::Slice(v.iter()),
            Repr::Shared { last, len } => {
                // The nodes are linked from the last: collect them, then visit in reverse.
                let mut nodes = Vec::with_capacity(*len);
                let mut node = last.as_deref();
                while let Some(n) = node {
                    nodes.push(&n.item);
                    node = n.prev.as_deref();
                }
                Iter::Nodes(nodes)
            }
        }
    }

    /// The elements in a `Vec`, first to last.
    pub fn to_vec(&self) -> Vec<T>
    where
        T: Clone,
    {
        self.iter().cloned().collect()
    }
}

impl<T> std::ops::Index<usize> for Trail<T> {
    type Output = T;
    #[inline]
    fn index(&self, i: usize) -> &T {
        let len = self.len();
        self.get(i)
            .unwrap_or_else(|| panic!("index {i} out of range for a trail of length {len}"))
    }
}

/// The iterator of [`Trail::iter`].
pub enum Iter<'a, T> {
    /// Over an owned trail's elements.
    Slice(std::slice::Iter<'a, T>),
    /// Node elements collected last-first, handed out from the end of the `Vec`.
    Nodes(Vec<&'a T>),
}

impl<'a, T> Iterator for Iter<'a, T> {
    type Item = &'a T;
    #[inline]
    fn next(&mut self) -> Option<&'a T> {
        match self {
            Iter::Slice(it) => it.next(),
            Iter::Nodes(nodes) => nodes.pop(),
        }
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = match self {
            Iter::Slice(it) => it.len(),
            Iter::Nodes(nodes) => nodes.len(),
        };
        (n, Some(n))
    }
}

impl<T> ExactSizeIterator for Iter<'_, T> {}

impl<'a, T> IntoIterator for &'a Trail<T> {
    type Item = &'a T;
    type IntoIter = Iter<'a, T>;
    fn into_iter(self) -> Iter<'a, T> {
        self.iter()
    }
}

impl<T> FromIterator<T> for Trail<T> {
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        Trail(Repr::Owned(iter.into_iter().collect()))
    }
}

impl<T: PartialEq> PartialEq for Trail<T> {
    /// Equal elements in the same order (owned and shared trails compare alike).
    fn eq(&self, other: &Self) -> bool {
        if let (Repr::Shared { last: Some(a), .. }, Repr::Shared { last: Some(b), .. }) =
            (&self.0, &other.0)
            && Arc::ptr_eq(a, b)
        {
            return true;
        }
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl<T: PartialEq> PartialEq<Vec<T>> for Trail<T> {
    fn eq(&self, other: &Vec<T>) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl<T: PartialEq> PartialEq<[T]> for Trail<T> {
    fn eq(&self, other: &[T]) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl<T: fmt::Debug> fmt::Debug for Trail<T> {
    /// Like a `Vec`: the elements in order.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}
