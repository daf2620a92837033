//! Joint states of the interface integration points, stored flat per
//! interface with a points-per-element count, so that the storage does not
//! depend on the element order (2 points per linear element, 3 per
//! quadratic one).

use tecon_contact::JointState;

/// The joint states of every integration point of one interface, element
/// after element: points `per_element·e .. per_element·(e + 1)` belong to
/// element `e`, in the element's point order.
#[derive(Debug, Clone, PartialEq)]
pub struct PointStates {
    per_element: usize,
    states: Vec<JointState>,
}

impl PointStates {
    /// Unloaded states of `n_elements` elements of `per_element` points each.
    pub fn new(n_elements: usize, per_element: usize) -> Self {
        PointStates {
            per_element,
            states: vec![JointState::default(); n_elements * per_element],
        }
    }

    /// Integration points per element.
    pub fn per_element(&self) -> usize {
        self.per_element
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.states.len().checked_div(self.per_element).unwrap_or(0)
    }

    /// The states of element `e`'s points.
    #[inline]
    pub fn element(&self, e: usize) -> &[JointState] {
        &self.states[e * self.per_element..(e + 1) * self.per_element]
    }

    /// The states of element `e`'s points, mutable.
    #[inline]
    pub fn element_mut(&mut self, e: usize) -> &mut [JointState] {
        &mut self.states[e * self.per_element..(e + 1) * self.per_element]
    }

    /// Element `e`'s states as an array of `P` points (`P` must be
    /// [`PointStates::per_element`]).
    #[inline]
    pub(crate) fn element_array<const P: usize>(&self, e: usize) -> &[JointState; P] {
        debug_assert_eq!(P, self.per_element);
        self.element(e)
            .try_into()
            .expect("points per element match the interface kernel")
    }

    /// Element `e`'s states as a mutable array of `P` points.
    #[inline]
    pub(crate) fn element_array_mut<const P: usize>(&mut self, e: usize) -> &mut [JointState; P] {
        debug_assert_eq!(P, self.per_element);
        self.element_mut(e)
            .try_into()
            .expect("points per element match the interface kernel")
    }

    /// The same elements with `per_element` points each, every point taking
    /// its element's first state (a seed of one state per element).
    pub(crate) fn broadcast(&self, per_element: usize) -> Self {
        let n = self.n_elements();
        PointStates {
            per_element,
            states: (0..n)
                .flat_map(|e| std::iter::repeat_n(self.element(e)[0], per_element))
                .collect(),
        }
    }

    /// All states, element-major.
    pub fn as_slice(&self) -> &[JointState] {
        &self.states
    }

    /// The states per element.
    pub fn elements(&self) -> impl ExactSizeIterator<Item = &[JointState]> + '_ {
        self.states.chunks_exact(self.per_element.max(1))
    }

    /// States from a flat element-major list of `per_element` points each.
    pub(crate) fn from_flat(per_element: usize, states: Vec<JointState>) -> Self {
        debug_assert!(per_element > 0 && states.len().is_multiple_of(per_element));
        PointStates {
            per_element,
            states,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_are_contiguous_slices_of_their_points() {
        let mut s = PointStates::new(4, 3);
        assert_eq!((s.per_element(), s.n_elements()), (3, 4));
        s.element_mut(2)[1].slip = 7.0;
        assert_eq!(s.as_slice()[7].slip, 7.0);
        assert_eq!(s.element_array::<3>(2)[1].slip, 7.0);
        assert_eq!(s.elements().len(), 4);
        let t = PointStates::from_flat(2, vec![JointState::default(); 10]);
        assert_eq!((t.per_element(), t.n_elements()), (2, 5));
        let b = s.broadcast(2);
        assert_eq!((b.per_element(), b.element(2)[1].slip), (2, 0.0));
        assert_eq!(PointStates::new(0, 2).n_elements(), 0);
    }
}
