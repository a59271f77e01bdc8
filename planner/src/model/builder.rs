//! Building domains and problems in Rust, with the same checks as PDDL input.

use super::{
    ActionTemplate, Atom, Domain, Literal, ModelError, OBJECT, Object, ObjectId, Param, Predicate, PredicateId,
    Problem, TemplateId, TypeDef, TypeId,
};

/// Builds a [`Domain`].
///
/// ```
/// use planner::model::DomainBuilder;
/// let mut d = DomainBuilder::new("door");
/// d.types(&["room"], "object")?;
/// d.predicate("in", &[("r", "room")])?;
/// d.predicate("open", &[])?;
/// d.action("go", &[("r", "room")])?.pre("open", &[])?.effect("in", &["r"])?;
/// d.action("open-door", &[])?.effect("open", &[])?;
/// let domain = d.build()?;
/// assert_eq!(domain.actions.len(), 2);
/// # Ok::<(), planner::model::ModelError>(())
/// ```
#[derive(Debug)]
pub struct DomainBuilder {
    domain: Domain,
}

/// Adds pre- and postconditions to the action just declared; made by
/// [`DomainBuilder::action`].
#[derive(Debug)]
pub struct ActionBuilder<'d> {
    domain: &'d mut Domain,
    action: usize,
}

/// Builds a [`Problem`] over a domain.
#[derive(Debug)]
pub struct ProblemBuilder {
    problem: Problem,
}

pub(crate) fn check_name(name: &str) -> Result<String, ModelError> {
    let lower = name.strip_prefix('?').unwrap_or(name).to_ascii_lowercase();
    let mut chars = lower.chars();
    let ok = chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if ok { Ok(lower) } else { Err(ModelError::BadName { name: name.to_string() }) }
}

fn type_name(domain: &Domain, ty: TypeId) -> String {
    domain.types.get(usize::from(ty)).map_or_else(|| "?".into(), |t| t.name.clone())
}

fn unknown_predicate(domain: &Domain, name: &str) -> ModelError {
    let declared: Vec<&str> = domain.predicates.iter().map(|p| p.name.as_str()).collect();
    ModelError::UnknownPredicate {
        name: name.to_string(),
        declared: if declared.is_empty() { "none".into() } else { declared.join(", ") },
    }
}

/// Resolves a predicate by name and checks the argument count.
fn predicate_for(domain: &Domain, name: &str, args: usize) -> Result<PredicateId, ModelError> {
    let id = domain.predicate(name).ok_or_else(|| unknown_predicate(domain, &name.to_ascii_lowercase()))?;
    let p = &domain.predicates[usize::from(id)];
    if p.params.len() != args {
        return Err(ModelError::WrongArity { predicate: p.name.clone(), expected: p.params.len(), found: args });
    }
    Ok(id)
}

fn params(domain: &Domain, list: &[(&str, &str)]) -> Result<Vec<Param>, ModelError> {
    let mut out: Vec<Param> = Vec::with_capacity(list.len());
    for &(name, ty) in list {
        let name = check_name(name)?;
        if out.iter().any(|p| p.name == name) {
            return Err(ModelError::DuplicateParameter { name });
        }
        let ty = domain.type_id(ty).ok_or_else(|| ModelError::UnknownType { name: ty.to_ascii_lowercase() })?;
        out.push(Param { name, ty });
    }
    Ok(out)
}

impl DomainBuilder {
    /// An empty domain (with the type `object` only).
    #[must_use]
    pub fn new(name: &str) -> Self {
        let types = vec![TypeDef { name: "object".into(), parent: None }];
        Self { domain: Domain { name: name.to_ascii_lowercase(), types, predicates: Vec::new(), actions: Vec::new() } }
    }

    /// Declares `names` as subtypes of `parent` (declared before, or `object`).
    ///
    /// # Errors
    /// [`ModelError::UnknownType`] for an undeclared parent, [`ModelError::DuplicateType`]
    /// for a name declared before, [`ModelError::BadName`].
    pub fn types(&mut self, names: &[&str], parent: &str) -> Result<&mut Self, ModelError> {
        let parent =
            self.domain.type_id(parent).ok_or_else(|| ModelError::UnknownType { name: parent.to_ascii_lowercase() })?;
        for &n in names {
            let name = check_name(n)?;
            if self.domain.type_id(&name).is_some() {
                return Err(ModelError::DuplicateType { name });
            }
            if self.domain.types.len() >= usize::from(u16::MAX) {
                return Err(ModelError::TooMany { what: "types", max: usize::from(u16::MAX) });
            }
            self.domain.types.push(TypeDef { name, parent: Some(parent) });
        }
        Ok(self)
    }

    /// Declares a type whose parent may be declared later (PDDL allows any order);
    /// [`DomainBuilder::set_parent`] fixes it.
    pub(crate) fn declare_type(&mut self, name: &str) -> Result<TypeId, ModelError> {
        let name = check_name(name)?;
        if let Some(id) = self.domain.type_id(&name) {
            return Ok(id);
        }
        let id = TypeId::try_from(self.domain.types.len())
            .map_err(|_| ModelError::TooMany { what: "types", max: usize::from(u16::MAX) })?;
        self.domain.types.push(TypeDef { name, parent: Some(OBJECT) });
        Ok(id)
    }

    /// Sets the parent of a declared type, refusing cycles.
    pub(crate) fn set_parent(&mut self, ty: TypeId, parent: TypeId) -> Result<(), ModelError> {
        if ty == OBJECT || self.domain.is_subtype(parent, ty) {
            return Err(ModelError::DuplicateType { name: type_name(&self.domain, ty) });
        }
        if let Some(t) = self.domain.types.get_mut(usize::from(ty)) {
            t.parent = Some(parent);
        }
        Ok(())
    }

    /// Declares a predicate with typed parameters `(name, type)`.
    ///
    /// # Errors
    /// [`ModelError::DuplicatePredicate`], [`ModelError::DuplicateParameter`],
    /// [`ModelError::UnknownType`], [`ModelError::BadName`].
    pub fn predicate(&mut self, name: &str, list: &[(&str, &str)]) -> Result<&mut Self, ModelError> {
        let name = check_name(name)?;
        if self.domain.predicate(&name).is_some() {
            return Err(ModelError::DuplicatePredicate { name });
        }
        if self.domain.predicates.len() + self.domain.actions.len() >= usize::from(u16::MAX) {
            return Err(ModelError::TooMany { what: "predicates and actions", max: usize::from(u16::MAX) });
        }
        let params = params(&self.domain, list)?;
        self.domain.predicates.push(Predicate { name, params });
        Ok(self)
    }

    /// Declares an action template with typed parameters `(name, type)`; add its
    /// conditions and effects through the returned [`ActionBuilder`].
    ///
    /// # Errors
    /// [`ModelError::DuplicateAction`], [`ModelError::DuplicateParameter`],
    /// [`ModelError::UnknownType`], [`ModelError::BadName`].
    pub fn action(&mut self, name: &str, list: &[(&str, &str)]) -> Result<ActionBuilder<'_>, ModelError> {
        let name = check_name(name)?;
        if self.domain.action(&name).is_some() {
            return Err(ModelError::DuplicateAction { name });
        }
        if self.domain.predicates.len() + self.domain.actions.len() >= usize::from(u16::MAX) || list.len() > 255 {
            return Err(ModelError::TooMany { what: "predicates and actions", max: usize::from(u16::MAX) });
        }
        let params = params(&self.domain, list)?;
        let action = self.domain.actions.len();
        self.domain.actions.push(ActionTemplate { name, params, pre: Vec::new(), effects: Vec::new() });
        Ok(ActionBuilder { domain: &mut self.domain, action })
    }

    /// The builder of an action declared before.
    pub(crate) fn action_mut(&mut self, id: TemplateId) -> ActionBuilder<'_> {
        ActionBuilder { domain: &mut self.domain, action: usize::from(id) }
    }

    /// The domain so far.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Checks that every action has an effect and returns the domain.
    ///
    /// # Errors
    /// [`ModelError::NoEffects`].
    pub fn build(self) -> Result<Domain, ModelError> {
        if let Some(a) = self.domain.actions.iter().find(|a| a.effects.is_empty()) {
            return Err(ModelError::NoEffects { action: a.name.clone() });
        }
        Ok(self.domain)
    }
}

impl ActionBuilder<'_> {
    fn literal(&self, positive: bool, predicate: &str, args: &[&str]) -> Result<Literal<u8>, ModelError> {
        let domain = &*self.domain;
        let id = predicate_for(domain, predicate, args.len())?;
        let pred = &domain.predicates[usize::from(id)];
        let action = &domain.actions[self.action];
        let mut out = Vec::with_capacity(args.len());
        for (pos, (&arg, want)) in args.iter().zip(&pred.params).enumerate() {
            let name = arg.strip_prefix('?').unwrap_or(arg).to_ascii_lowercase();
            let Some(i) = action.params.iter().position(|p| p.name == name) else {
                return Err(ModelError::UnknownParameter { name, action: action.name.clone() });
            };
            let ty = action.params[i].ty;
            if !domain.is_subtype(ty, want.ty) {
                return Err(ModelError::TypeMismatch {
                    predicate: pred.name.clone(),
                    position: pos + 1,
                    argument: format!("?{name}"),
                    expected: type_name(domain, want.ty),
                    found: type_name(domain, ty),
                });
            }
            // At most 255 parameters: checked when the action was declared.
            out.push(i as u8);
        }
        Ok(Literal { positive, atom: Atom { predicate: id, args: out } })
    }

    /// Adds the precondition `predicate(args)` (`args` are parameter names).
    ///
    /// # Errors
    /// [`ModelError::UnknownPredicate`], [`ModelError::WrongArity`],
    /// [`ModelError::UnknownParameter`], [`ModelError::TypeMismatch`].
    pub fn pre(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let l = self.literal(true, predicate, args)?;
        self.domain.actions[self.action].pre.push(l);
        Ok(self)
    }

    /// Adds the negative precondition `not predicate(args)`.
    ///
    /// # Errors
    /// As [`ActionBuilder::pre`].
    pub fn pre_not(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let l = self.literal(false, predicate, args)?;
        self.domain.actions[self.action].pre.push(l);
        Ok(self)
    }

    /// Adds the postcondition `predicate(args)`: the action makes it true.
    ///
    /// # Errors
    /// As [`ActionBuilder::pre`].
    pub fn effect(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let l = self.literal(true, predicate, args)?;
        self.domain.actions[self.action].effects.push(l);
        Ok(self)
    }

    /// Adds the postcondition `not predicate(args)`: the action makes it false.
    ///
    /// # Errors
    /// As [`ActionBuilder::pre`].
    pub fn effect_not(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let l = self.literal(false, predicate, args)?;
        self.domain.actions[self.action].effects.push(l);
        Ok(self)
    }
}

impl ProblemBuilder {
    /// An empty problem over `domain`.
    #[must_use]
    pub fn new(name: &str, domain: &Domain) -> Self {
        Self {
            problem: Problem {
                name: name.to_ascii_lowercase(),
                domain: domain.clone(),
                objects: Vec::new(),
                init: Vec::new(),
                goal: Vec::new(),
            },
        }
    }

    /// Declares objects of type `ty`, in order (their indices are leaf arguments).
    ///
    /// # Errors
    /// [`ModelError::UnknownType`], [`ModelError::DuplicateObject`], [`ModelError::BadName`].
    pub fn objects(&mut self, names: &[&str], ty: &str) -> Result<&mut Self, ModelError> {
        let ty =
            self.problem.domain.type_id(ty).ok_or_else(|| ModelError::UnknownType { name: ty.to_ascii_lowercase() })?;
        for &n in names {
            let name = check_name(n)?;
            if self.problem.object(&name).is_some() {
                return Err(ModelError::DuplicateObject { name });
            }
            if self.problem.objects.len() >= usize::from(u16::MAX - 1) {
                return Err(ModelError::TooMany { what: "objects", max: usize::from(u16::MAX - 1) });
            }
            self.problem.objects.push(Object { name, ty });
        }
        Ok(self)
    }

    fn atom(&self, predicate: &str, args: &[&str]) -> Result<Atom<ObjectId>, ModelError> {
        let p = &self.problem;
        let id = predicate_for(&p.domain, predicate, args.len())?;
        let pred = &p.domain.predicates[usize::from(id)];
        let mut out = Vec::with_capacity(args.len());
        for (pos, (&arg, want)) in args.iter().zip(&pred.params).enumerate() {
            let o = p.object(arg).ok_or_else(|| ModelError::UnknownObject { name: arg.to_ascii_lowercase() })?;
            let ty = p.objects[usize::from(o)].ty;
            if !p.domain.is_subtype(ty, want.ty) {
                return Err(ModelError::TypeMismatch {
                    predicate: pred.name.clone(),
                    position: pos + 1,
                    argument: p.objects[usize::from(o)].name.clone(),
                    expected: type_name(&p.domain, want.ty),
                    found: type_name(&p.domain, ty),
                });
            }
            out.push(o);
        }
        Ok(Atom { predicate: id, args: out })
    }

    /// Makes `predicate(objects)` true in the initial state.
    ///
    /// # Errors
    /// [`ModelError::UnknownPredicate`], [`ModelError::WrongArity`],
    /// [`ModelError::UnknownObject`], [`ModelError::TypeMismatch`].
    pub fn init(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let a = self.atom(predicate, args)?;
        if !self.problem.init.contains(&a) {
            self.problem.init.push(a);
        }
        Ok(self)
    }

    /// Adds the goal condition `predicate(objects)`.
    ///
    /// # Errors
    /// As [`ProblemBuilder::init`].
    pub fn goal(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let atom = self.atom(predicate, args)?;
        self.problem.goal.push(Literal { positive: true, atom });
        Ok(self)
    }

    /// Adds the goal condition `not predicate(objects)`.
    ///
    /// # Errors
    /// As [`ProblemBuilder::init`].
    pub fn goal_not(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let atom = self.atom(predicate, args)?;
        self.problem.goal.push(Literal { positive: false, atom });
        Ok(self)
    }

    /// Checks that there is a goal and returns the problem.
    ///
    /// # Errors
    /// [`ModelError::EmptyGoal`].
    pub fn build(self) -> Result<Problem, ModelError> {
        if self.problem.goal.is_empty() {
            return Err(ModelError::EmptyGoal);
        }
        Ok(self.problem)
    }
}
