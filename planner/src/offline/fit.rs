//! Trees that fit the controller they are for ([`Fit`]): the closure over
//! disturbances is cut until the image fits.

use bt_core::Catalog;

use super::Plan;
use crate::PlanError;
use crate::options::{Fit, Options};

pub use bt_formats::image::Size;

/// The size of a tree and its value table as a controller holds it.
///
/// # Errors
/// [`PlanError::TooBig`] when the tree does not make an image at all (more nodes or
/// values than an image holds).
pub fn size_of(nodes: &[bt_core::Node], values: &[u16]) -> Result<Size, PlanError> {
    bt_formats::image::Image::new(nodes)
        .values(values)
        .size()
        .map_err(|e| PlanError::TooBig { what: format!("the tree makes no image: {e}") })
}

/// How a tree was made to fit ([`Plan::fit`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fitted {
    /// The tree's size.
    pub size: Size,
    /// Whether it is within the [`Fit`] asked for.
    pub fits: bool,
    /// When the closure over disturbances was given fewer nodes than
    /// [`Options::close_nodes`] so that the tree fits: that node budget (0: no closure
    /// at all); for a closure whose rules were chosen by the disturbed episodes they
    /// save ([`Fitted::by_episodes`]), the tree's nodes.
    pub cut: Option<usize>,
    /// For a regression tree whose closure was cut: the closure's groups of rules (a
    /// way back from a disturbed state, or an undo rule) kept, of all it added.
    pub ways: Option<(u32, u32)>,
    /// Whether the groups kept were chosen by the disturbed episodes they save per byte
    /// (else in the closure's order, nearest the tree's path first).
    pub by_episodes: bool,
}

impl std::fmt::Display for Fitted {
    /// `image 15,912 bytes, 2,104 nodes; the closure over disturbances cut to 2,400
    /// nodes to fit`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::wording::count;
        write!(f, "image {}, {}", count(self.size.bytes, "byte"), count(self.size.nodes, "node"))?;
        match self.cut {
            Some(0) => write!(f, "; the closure over disturbances left out to fit")?,
            Some(n) => write!(f, "; the closure over disturbances cut to {} to fit", count(n, "node"))?,
            None => {}
        }
        if let Some((kept, of)) = self.ways {
            write!(f, " ({kept} of {of} ways back kept")?;
            if self.by_episodes {
                write!(f, ", chosen by the disturbed episodes they save per byte")?;
            }
            write!(f, ")")?;
        }
        if !self.fits {
            write!(f, "; does not fit")?;
        }
        Ok(())
    }
}

/// The sentence of [`PlanError::TooBig`] for a tree of `size` that must fit `fit`.
pub(super) fn too_big(size: Size, fit: Fit) -> PlanError {
    use crate::wording::count;
    let what = if size.bytes > fit.bytes {
        format!("its image has {}, more than the {} asked for", count(size.bytes, "byte"), count(fit.bytes, "byte"))
    } else {
        format!("it has {}, more than the {} asked for", count(size.nodes, "node"), count(fit.nodes, "node"))
    };
    PlanError::TooBig { what: format!("the tree does not fit even without its closure over disturbances: {what}") }
}

/// The first node budget of a closure that must fit `options.fit`, for a tree of
/// `plain` size without it: [`Options::close_nodes`], or as many nodes as the bytes
/// allowed hold at the bytes a node of the plain tree takes, if fewer; `counted`
/// nodes for each node of the tree, as the closure counts them.
pub(super) fn first_budget(options: Options, plain: Size, counted: f64) -> usize {
    let per_node = plain.bytes as f64 / plain.nodes.max(1) as f64;
    let held = |n: usize| (n as f64 * counted) as usize;
    options.close_nodes.min(held((options.fit.bytes as f64 / per_node) as usize)).min(held(options.fit.nodes))
}

/// Makes a tree with `make(budget)`, the closure over disturbances within `budget`
/// nodes, that fits `options.fit`. The tree without any closure (`make(0)`) gives the
/// bytes a node takes; the first budget is [`Options::close_nodes`], or fewer where
/// that many nodes would not fit. While the tree does not fit, the budget shrinks in
/// proportion to how far over it is (and a tenth more), at most five times, then the
/// closure is left out. A tree that does not fit even then is returned with
/// [`Fitted::fits`] false.
///
/// # Errors
/// From `make`.
pub(super) fn within<C: Catalog>(
    options: Options,
    mut make: impl FnMut(usize) -> Result<Plan<C>, PlanError>,
) -> Result<Plan<C>, PlanError> {
    let fit = options.fit;
    let measure = |mut p: Plan<C>, cut: Option<usize>| -> Result<Plan<C>, PlanError> {
        let size = size_of(&p.nodes, &p.values)?;
        p.fit = Fitted { size, fits: fit.admits(size), cut, ..Fitted::default() };
        Ok(p)
    };
    let plain = measure(make(0)?, None)?;
    if options.close_nodes == 0 || !plain.fit.fits {
        return Ok(Plan { fit: Fitted { cut: (options.close_nodes > 0).then_some(0), ..plain.fit }, ..plain });
    }
    let mut budget = first_budget(options, plain.fit.size, 1.0);
    let mut tries = 0;
    loop {
        let mut p = make(budget)?;
        p.first = p.first.min(plain.first);
        // Cut only where the closure stopped short of the states it would look at.
        let short = p.closed.is_some_and(|c| !c.complete);
        let cut = (budget < options.close_nodes && short).then_some(budget);
        let p = measure(p, cut)?;
        if p.fit.fits {
            return Ok(p);
        }
        let size = p.fit.size;
        let over = (fit.bytes as f64 / size.bytes as f64).min(fit.nodes as f64 / size.nodes as f64);
        let next = (budget.min(size.nodes) as f64 * over * 0.9) as usize;
        if tries >= 4 || next < 16 {
            return Ok(Plan { fit: Fitted { cut: Some(0), ..plain.fit }, ..plain });
        }
        budget = next.min(budget - 1);
        tries += 1;
    }
}
