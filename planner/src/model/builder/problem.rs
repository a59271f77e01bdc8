//! Building a problem over a domain, with the same checks as PDDL input.

use std::collections::HashMap;

use super::{MAX_OBJECTS, Names, NamesRef, atom_of, check_declared};
use crate::model::{
    Atom, Condition, Domain, FunctionId, FunctionValue, Literal, ModelError, Object, ObjectId, Problem, Term, TypeId,
};

/// Builds a [`Problem`] over a domain.
#[derive(Debug)]
pub struct ProblemBuilder {
    problem: Problem,
    names: Names,
    objects: HashMap<String, ObjectId>,
    init: std::collections::HashSet<Atom<ObjectId>>,
    valued: HashMap<(FunctionId, Vec<ObjectId>), usize>,
}

impl ProblemBuilder {
    /// An empty problem over `domain`; the domain's constants are its first objects.
    #[must_use]
    pub fn new(name: &str, domain: &Domain) -> Self {
        let names = Names::of(domain);
        let objects = names.constants.clone();
        Self {
            problem: Problem {
                name: name.to_ascii_lowercase(),
                domain: domain.clone(),
                objects: domain.constants.clone(),
                init: Vec::new(),
                functions: Vec::new(),
                goal: Vec::new(),
                metric: false,
            },
            names,
            objects,
            init: std::collections::HashSet::new(),
            valued: HashMap::new(),
        }
    }

    pub(crate) fn names(&self) -> NamesRef<'_> {
        NamesRef(&self.names)
    }

    /// The problem so far.
    #[must_use]
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The object of a name, if declared (constants included).
    #[must_use]
    pub fn object(&self, name: &str) -> Option<ObjectId> {
        self.objects.get(&name.to_ascii_lowercase()).copied()
    }

    /// Declares objects of type `ty`, in order (their indices are leaf arguments).
    ///
    /// # Errors
    /// [`ModelError::UnknownType`], [`ModelError::DuplicateObject`], [`ModelError::BadName`].
    pub fn objects(&mut self, names: &[&str], ty: &str) -> Result<&mut Self, ModelError> {
        let lower = ty.to_ascii_lowercase();
        let ty = *self.names.types.get(&lower).ok_or(ModelError::UnknownType { name: lower })?;
        for &n in names {
            self.object_of_type(n, ty)?;
        }
        Ok(self)
    }

    /// Declares one object of type `ty`. A constant of the domain declared again with
    /// the same name is the same object (as planners read it), if its type fits.
    pub(crate) fn object_of_type(&mut self, name: &str, ty: TypeId) -> Result<ObjectId, ModelError> {
        let name = check_declared(name, "an object")?;
        if let Some(&id) = self.objects.get(&name) {
            let is_constant = usize::from(id) < self.problem.domain.constants.len();
            if is_constant && self.problem.objects[usize::from(id)].ty == ty {
                return Ok(id);
            }
            return Err(ModelError::DuplicateObject { name });
        }
        if self.problem.objects.len() >= usize::from(MAX_OBJECTS) {
            return Err(ModelError::TooMany { what: "objects", max: usize::from(MAX_OBJECTS) });
        }
        let id = self.problem.objects.len() as ObjectId;
        self.objects.insert(name.clone(), id);
        self.problem.objects.push(Object { name, ty });
        Ok(id)
    }

    fn atom(&self, predicate: &str, args: &[&str]) -> Result<Atom<ObjectId>, ModelError> {
        let mut terms = Vec::with_capacity(args.len());
        for &arg in args {
            let lower = arg.to_ascii_lowercase();
            let o = *self.objects.get(&lower).ok_or(ModelError::UnknownObject { name: lower })?;
            let obj = &self.problem.objects[usize::from(o)];
            terms.push((Term::Object(o), obj.ty, obj.name.clone()));
        }
        let a = atom_of(&self.problem.domain, &NamesRef(&self.names), predicate, &terms)?;
        Ok(Atom {
            predicate: a.predicate,
            args: a
                .args
                .iter()
                .map(|t| match t {
                    Term::Object(o) => *o,
                    Term::Var(_) => 0,
                })
                .collect(),
        })
    }

    /// Makes `predicate(objects)` true in the initial state.
    ///
    /// # Errors
    /// [`ModelError::UnknownPredicate`], [`ModelError::WrongArity`],
    /// [`ModelError::UnknownObject`], [`ModelError::TypeMismatch`].
    pub fn init(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let a = self.atom(predicate, args)?;
        self.init_atom(a);
        Ok(self)
    }

    /// Adds a checked atom to the initial state (once).
    pub(crate) fn init_atom(&mut self, a: Atom<ObjectId>) {
        if self.init.insert(a.clone()) {
            self.problem.init.push(a);
        }
    }

    /// Adds the goal condition `predicate(objects)`.
    ///
    /// # Errors
    /// As [`ProblemBuilder::init`].
    pub fn goal(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let atom = self.atom(predicate, args)?;
        let atom = Atom { predicate: atom.predicate, args: atom.args.into_iter().map(Term::Object).collect() };
        self.problem.goal.push(Condition::Literal(Literal { positive: true, atom }));
        Ok(self)
    }

    /// Adds the goal condition `not predicate(objects)`.
    ///
    /// # Errors
    /// As [`ProblemBuilder::init`].
    pub fn goal_not(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let atom = self.atom(predicate, args)?;
        let atom = Atom { predicate: atom.predicate, args: atom.args.into_iter().map(Term::Object).collect() };
        self.problem.goal.push(Condition::Literal(Literal { positive: false, atom }));
        Ok(self)
    }

    /// Adds a goal formula (over objects and its own quantified variables).
    pub fn goal_condition(&mut self, c: Condition) -> &mut Self {
        self.problem.goal.push(c);
        self
    }

    /// Sets `(= (function args...) value)` in the initial state.
    ///
    /// # Errors
    /// [`ModelError::DuplicateFunction`] when the term was valued before.
    pub fn function_value(&mut self, function: FunctionId, args: Vec<ObjectId>, value: u32) -> Result<(), ModelError> {
        let name = self.problem.domain.functions.get(usize::from(function)).map_or("?", |f| f.name.as_str());
        if self.valued.insert((function, args.clone()), self.problem.functions.len()).is_some() {
            return Err(ModelError::DuplicateFunction { name: name.to_string() });
        }
        self.problem.functions.push(FunctionValue { function, args, value });
        Ok(())
    }

    /// Asks to minimize `total-cost` (`(:metric minimize (total-cost))`).
    pub fn minimize_total_cost(&mut self) -> &mut Self {
        self.problem.metric = true;
        self
    }

    /// Checks that there is a goal and returns the problem.
    ///
    /// # Errors
    /// [`ModelError::EmptyGoal`].
    pub fn build(self) -> Result<Problem, ModelError> {
        let empty = self.problem.goal.iter().all(|c| matches!(c, Condition::And(v) if v.is_empty()));
        if empty {
            return Err(ModelError::EmptyGoal);
        }
        Ok(self.problem)
    }
}
