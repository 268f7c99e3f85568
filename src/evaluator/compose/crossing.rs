//! One crossover as composing and scoring its children read it.

use super::PartClasses;
use crate::evaluator::mesh::state::MeshState;
use crate::heightfield::Heightfield;
use std::sync::Arc;

/// What a crossover's children are made from, passed as one: the height field, the parents
/// A and B (scored on it, their disc boxes filled) and both parents' triangles classified
/// against the crossover's parts. Composing a child
/// ([`Evaluator::compose_parts`](crate::evaluator::Evaluator::compose_parts)) and scoring one
/// without its mesh ([`PartScores`](crate::evaluator::PartScores)) read all of them together.
#[derive(Clone, Copy, Debug)]
pub struct Crossing<'a> {
    /// The height field both parents are scored on.
    pub hf: &'a Arc<Heightfield>,
    /// Parent A, then parent B.
    pub parents: [&'a MeshState; 2],
    /// The parents' triangles classified against the crossover's parts.
    pub classes: &'a PartClasses,
}

impl Crossing<'_> {
    /// Was the classification made for these parents as they are now?
    pub(crate) fn classes_fit(&self) -> bool {
        let [a, b] = self.parents;
        self.classes.is_for(a, b)
    }
}
