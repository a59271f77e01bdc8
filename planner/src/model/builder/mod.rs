//! Building domains and problems in Rust, with the same checks as PDDL input.
//!
//! Names are looked up through hash maps while building, so a domain or problem of
//! many declarations builds in time linear in its size.

use std::collections::HashMap;

mod problem;

pub use problem::ProblemBuilder;

use super::{
    ActionTemplate, Atom, Condition, CostTerm, Domain, Effect, Function, FunctionId, Literal, ModelError, OBJECT,
    Object, ObjectId, Param, Predicate, PredicateId, TemplateId, Term, TypeDef, TypeId, Var,
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
    names: Names,
}

/// Name → id maps of a domain under construction.
#[derive(Debug, Default, Clone)]
struct Names {
    types: HashMap<String, TypeId>,
    predicates: HashMap<String, PredicateId>,
    actions: HashMap<String, TemplateId>,
    functions: HashMap<String, FunctionId>,
    constants: HashMap<String, ObjectId>,
}

impl Names {
    fn of(d: &Domain) -> Self {
        let mut n = Self::default();
        for (i, t) in d.types.iter().enumerate() {
            n.types.insert(t.name.clone(), i as TypeId);
        }
        for (i, p) in d.predicates.iter().enumerate() {
            n.predicates.insert(p.name.clone(), i as PredicateId);
        }
        for (i, a) in d.actions.iter().enumerate() {
            n.actions.insert(a.name.clone(), i as TemplateId);
        }
        for (i, f) in d.functions.iter().enumerate() {
            n.functions.insert(f.name.clone(), i as FunctionId);
        }
        for (i, c) in d.constants.iter().enumerate() {
            n.constants.insert(c.name.clone(), i as ObjectId);
        }
        n
    }
}

/// Adds pre- and postconditions to the action just declared; made by
/// [`DomainBuilder::action`].
#[derive(Debug)]
pub struct ActionBuilder<'d> {
    domain: &'d mut Domain,
    names: &'d Names,
    action: usize,
    /// Whether `action` indexes [`Domain::axioms`] rather than [`Domain::actions`].
    axiom: bool,
}

/// PDDL's reserved words: never a name of a predicate, action, type or object.
const RESERVED: &[&str] = &[
    "and",
    "or",
    "not",
    "imply",
    "exists",
    "forall",
    "when",
    "either",
    "define",
    "increase",
    "decrease",
    "assign",
    "scale-up",
    "scale-down",
    "minimize",
    "maximize",
    "at",
    "over",
    "preference",
];

/// Checks a name: letters, digits, `-` and `_`, starting with a letter or a digit.
/// Variables are checked by [`check_variable`]; a `?` anywhere else is refused.
pub(crate) fn check_name(name: &str) -> Result<String, ModelError> {
    let lower = name.to_ascii_lowercase();
    let mut chars = lower.chars();
    let ok = chars.next().is_some_and(|c| c.is_ascii_alphanumeric())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if ok { Ok(lower) } else { Err(ModelError::BadName { name: name.to_string() }) }
}

/// Checks a name that declares something (`what`): a valid name, not a reserved word.
/// `at` is allowed for predicates and objects (domains use `(at ?x ?y)` everywhere;
/// only a timed `(at end ...)` would make it ambiguous, and this model has no time).
pub(crate) fn check_declared(name: &str, what: &'static str) -> Result<String, ModelError> {
    let lower = check_name(name)?;
    if RESERVED.contains(&lower.as_str()) && lower != "at" && lower != "over" {
        return Err(ModelError::ReservedName { name: lower, what });
    }
    Ok(lower)
}

/// Checks a variable or parameter name; a leading `?` is optional in the builders, so
/// `?x` and `x` name the same parameter.
pub(crate) fn check_variable(name: &str) -> Result<String, ModelError> {
    check_name(name.strip_prefix('?').unwrap_or(name)).map_err(|_| ModelError::BadName { name: name.to_string() })
}

fn type_name(domain: &Domain, ty: TypeId) -> String {
    domain.types.get(usize::from(ty)).map_or_else(|| "?".into(), |t| t.name.clone())
}

fn unknown_predicate(domain: &Domain, name: &str) -> ModelError {
    let mut declared: Vec<&str> = domain.predicates.iter().take(20).map(|p| p.name.as_str()).collect();
    if domain.predicates.len() > 20 {
        declared.push("...");
    }
    ModelError::UnknownPredicate {
        name: name.to_string(),
        declared: if declared.is_empty() { "none".into() } else { declared.join(", ") },
    }
}

/// Resolves a predicate by name and checks the argument count.
fn predicate_for(domain: &Domain, names: &Names, name: &str, args: usize) -> Result<PredicateId, ModelError> {
    let lower = name.to_ascii_lowercase();
    let id = *names.predicates.get(&lower).ok_or_else(|| unknown_predicate(domain, &lower))?;
    let p = &domain.predicates[usize::from(id)];
    if p.params.len() != args {
        return Err(ModelError::WrongArity { predicate: p.name.clone(), expected: p.params.len(), found: args });
    }
    Ok(id)
}

/// Checks an atom whose arguments have the given types (`(term, type, text)`): the
/// predicate exists, the count fits, and each argument's type can be the parameter's.
pub(crate) fn atom_of(
    domain: &Domain,
    names: &NamesRef<'_>,
    predicate: &str,
    args: &[(Term, TypeId, String)],
) -> Result<Atom<Term>, ModelError> {
    let id = predicate_for(domain, names.0, predicate, args.len())?;
    let pred = &domain.predicates[usize::from(id)];
    for (pos, ((_, ty, text), want)) in args.iter().zip(&pred.params).enumerate() {
        if !domain.overlaps(*ty, want.ty) {
            return Err(ModelError::TypeMismatch {
                predicate: pred.name.clone(),
                position: pos + 1,
                argument: text.clone(),
                expected: type_name(domain, want.ty),
                found: type_name(domain, *ty),
            });
        }
    }
    Ok(Atom { predicate: id, args: args.iter().map(|a| a.0).collect() })
}

/// The name maps of a domain, for the PDDL reader.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NamesRef<'a>(&'a Names);

impl NamesRef<'_> {
    pub(crate) fn constant(&self, name: &str) -> Option<ObjectId> {
        self.0.constants.get(name).copied()
    }
    pub(crate) fn function(&self, name: &str) -> Option<FunctionId> {
        self.0.functions.get(name).copied()
    }
    pub(crate) fn type_id(&self, name: &str) -> Option<TypeId> {
        self.0.types.get(name).copied()
    }
}

fn params(domain: &Domain, names: &Names, list: &[(&str, &str)]) -> Result<Vec<Param>, ModelError> {
    let mut out: Vec<Param> = Vec::with_capacity(list.len());
    let mut seen = std::collections::HashSet::with_capacity(list.len());
    for &(name, ty) in list {
        let name = check_variable(name)?;
        if !seen.insert(name.clone()) {
            return Err(ModelError::DuplicateParameter { name });
        }
        let lower = ty.to_ascii_lowercase();
        let ty = *names.types.get(&lower).ok_or(ModelError::UnknownType { name: lower })?;
        out.push(Param { name, ty });
    }
    let _ = domain;
    Ok(out)
}

const MAX_BEHAVIORS: usize = u16::MAX as usize;

impl DomainBuilder {
    /// Records a requirement the domain declares.
    pub fn requirement(&mut self, name: &str) {
        let name = name.to_ascii_lowercase();
        if !self.domain.requirements.contains(&name) {
            self.domain.requirements.push(name);
        }
    }

    /// An empty domain (with the type `object` only).
    #[must_use]
    pub fn new(name: &str) -> Self {
        let types = vec![TypeDef { name: "object".into(), parent: None, either: Vec::new() }];
        let domain = Domain {
            name: name.to_ascii_lowercase(),
            types,
            constants: Vec::new(),
            predicates: Vec::new(),
            functions: Vec::new(),
            actions: Vec::new(),
            axioms: Vec::new(),
            requirements: Vec::new(),
        };
        let names = Names::of(&domain);
        Self { domain, names }
    }

    pub(crate) fn names(&self) -> NamesRef<'_> {
        NamesRef(&self.names)
    }

    /// Declares `names` as subtypes of `parent` (declared before, or `object`).
    ///
    /// # Errors
    /// [`ModelError::UnknownType`] for an undeclared parent, [`ModelError::DuplicateType`]
    /// for a name declared before, [`ModelError::BadName`].
    pub fn types(&mut self, names: &[&str], parent: &str) -> Result<&mut Self, ModelError> {
        let lower = parent.to_ascii_lowercase();
        let parent = *self.names.types.get(&lower).ok_or(ModelError::UnknownType { name: lower })?;
        for &n in names {
            let name = check_declared(n, "a type")?;
            if self.names.types.contains_key(&name) {
                return Err(ModelError::DuplicateType { name });
            }
            self.push_type(TypeDef { name, parent: Some(parent), either: Vec::new() })?;
        }
        Ok(self)
    }

    fn push_type(&mut self, t: TypeDef) -> Result<TypeId, ModelError> {
        let id = TypeId::try_from(self.domain.types.len())
            .ok()
            .filter(|&i| i < u16::MAX)
            .ok_or(ModelError::TooMany { what: "types", max: usize::from(u16::MAX - 1) })?;
        self.names.types.insert(t.name.clone(), id);
        self.domain.types.push(t);
        Ok(id)
    }

    /// Declares a type whose parent may be declared later (PDDL allows any order);
    /// [`DomainBuilder::set_parent`] fixes it.
    pub(crate) fn declare_type(&mut self, name: &str) -> Result<TypeId, ModelError> {
        let name = check_declared(name, "a type")?;
        if let Some(&id) = self.names.types.get(&name) {
            return Ok(id);
        }
        self.push_type(TypeDef { name, parent: Some(OBJECT), either: Vec::new() })
    }

    /// The union type `(either a b ...)` of declared types (made once, then reused).
    ///
    /// # Errors
    /// [`ModelError::UnknownType`].
    pub fn either(&mut self, members: &[&str]) -> Result<TypeId, ModelError> {
        let mut ids = Vec::with_capacity(members.len());
        for m in members {
            let lower = m.to_ascii_lowercase();
            let id = *self.names.types.get(&lower).ok_or(ModelError::UnknownType { name: lower })?;
            if !ids.contains(&id) {
                ids.push(id);
            }
        }
        if let [one] = ids[..] {
            return Ok(one);
        }
        let name =
            format!("(either {})", ids.iter().map(|&i| type_name(&self.domain, i)).collect::<Vec<_>>().join(" "));
        if let Some(&id) = self.names.types.get(&name) {
            return Ok(id);
        }
        self.push_type(TypeDef { name, parent: None, either: ids })
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

    /// Declares constants of type `ty`: objects every problem of the domain has.
    ///
    /// # Errors
    /// [`ModelError::UnknownType`], [`ModelError::DuplicateObject`],
    /// [`ModelError::BadName`], [`ModelError::TooMany`].
    pub fn constants(&mut self, names: &[&str], ty: &str) -> Result<&mut Self, ModelError> {
        let lower = ty.to_ascii_lowercase();
        let ty = *self.names.types.get(&lower).ok_or(ModelError::UnknownType { name: lower })?;
        self.constants_of_type(names, ty)?;
        Ok(self)
    }

    pub(crate) fn constants_of_type(&mut self, names: &[&str], ty: TypeId) -> Result<(), ModelError> {
        for &n in names {
            let name = check_declared(n, "a constant")?;
            if self.names.constants.contains_key(&name) {
                return Err(ModelError::DuplicateObject { name });
            }
            if self.domain.constants.len() >= usize::from(MAX_OBJECTS) {
                return Err(ModelError::TooMany { what: "objects", max: usize::from(MAX_OBJECTS) });
            }
            self.names.constants.insert(name.clone(), self.domain.constants.len() as ObjectId);
            self.domain.constants.push(Object { name, ty });
        }
        Ok(())
    }

    /// Declares a predicate with typed parameters `(name, type)`.
    ///
    /// # Errors
    /// [`ModelError::DuplicatePredicate`], [`ModelError::DuplicateParameter`],
    /// [`ModelError::UnknownType`], [`ModelError::BadName`].
    pub fn predicate(&mut self, name: &str, list: &[(&str, &str)]) -> Result<&mut Self, ModelError> {
        let name = check_declared(name, "a predicate")?;
        if self.names.predicates.contains_key(&name) {
            return Err(ModelError::DuplicatePredicate { name });
        }
        if self.domain.predicates.len() + self.domain.actions.len() >= MAX_BEHAVIORS {
            return Err(ModelError::TooMany { what: "predicates and actions", max: MAX_BEHAVIORS });
        }
        if list.len() > 255 {
            return Err(ModelError::TooMany { what: "parameters of a predicate", max: 255 });
        }
        let params = params(&self.domain, &self.names, list)?;
        self.names.predicates.insert(name.clone(), self.domain.predicates.len() as PredicateId);
        self.domain.predicates.push(Predicate { name, params });
        Ok(self)
    }

    /// Declares a function (`:functions`): `total-cost`, or a static one that action
    /// costs read.
    ///
    /// # Errors
    /// [`ModelError::DuplicateFunction`], [`ModelError::UnknownType`],
    /// [`ModelError::BadName`].
    pub fn function(&mut self, name: &str, list: &[(&str, &str)]) -> Result<FunctionId, ModelError> {
        let name = check_declared(name, "a function")?;
        if self.names.functions.contains_key(&name) {
            return Err(ModelError::DuplicateFunction { name });
        }
        if self.domain.functions.len() >= usize::from(u16::MAX) || list.len() > 255 {
            return Err(ModelError::TooMany { what: "functions", max: usize::from(u16::MAX) });
        }
        let params = params(&self.domain, &self.names, list)?;
        let id = self.domain.functions.len() as FunctionId;
        self.names.functions.insert(name.clone(), id);
        self.domain.functions.push(Function { name, params });
        Ok(id)
    }

    /// Declares an action template with typed parameters `(name, type)`; add its
    /// conditions and effects through the returned [`ActionBuilder`].
    ///
    /// # Errors
    /// [`ModelError::DuplicateAction`], [`ModelError::DuplicateParameter`],
    /// [`ModelError::UnknownType`], [`ModelError::BadName`], [`ModelError::ReservedName`].
    pub fn action(&mut self, name: &str, list: &[(&str, &str)]) -> Result<ActionBuilder<'_>, ModelError> {
        let name = check_declared(name, "an action")?;
        if self.names.actions.contains_key(&name) {
            return Err(ModelError::DuplicateAction { name });
        }
        if self.domain.predicates.len() + self.domain.actions.len() >= MAX_BEHAVIORS {
            return Err(ModelError::TooMany { what: "predicates and actions", max: MAX_BEHAVIORS });
        }
        if list.len() > 255 {
            return Err(ModelError::TooManyVariables { action: name });
        }
        let params = params(&self.domain, &self.names, list)?;
        let action = self.domain.actions.len();
        self.names.actions.insert(name.clone(), action as TemplateId);
        let vars = params.iter().map(|p| p.ty).collect();
        self.domain.actions.push(ActionTemplate {
            name,
            params,
            vars,
            pre: Vec::new(),
            effects: Vec::new(),
            cost: Vec::new(),
        });
        Ok(ActionBuilder { domain: &mut self.domain, names: &self.names, action, axiom: false })
    }

    /// The builder of an action declared before.
    pub(crate) fn action_mut(&mut self, id: TemplateId) -> ActionBuilder<'_> {
        ActionBuilder { domain: &mut self.domain, names: &self.names, action: usize::from(id), axiom: false }
    }

    /// The builder of a rule declared before with [`DomainBuilder::derived`].
    pub(crate) fn derived_mut(&mut self, id: usize) -> ActionBuilder<'_> {
        ActionBuilder { domain: &mut self.domain, names: &self.names, action: id, axiom: true }
    }

    /// The domain so far.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// A rule of the derived predicate `predicate` (`(:derived (p ?x - t ...) body)`),
    /// with its head's parameters `list` (names and types, one per argument of the
    /// predicate); its body is added with [`ActionBuilder::condition`] (or `pre`).
    ///
    /// # Errors
    /// [`ModelError::UnknownPredicate`], [`ModelError::WrongArity`],
    /// [`ModelError::DuplicateParameter`], [`ModelError::UnknownType`].
    pub fn derived(&mut self, predicate: &str, list: &[(&str, &str)]) -> Result<ActionBuilder<'_>, ModelError> {
        let name = predicate.to_ascii_lowercase();
        let Some(&p) = self.names.predicates.get(&name) else {
            let declared = self.domain.predicates.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ");
            return Err(ModelError::UnknownPredicate { name, declared });
        };
        let expected = self.domain.predicates[usize::from(p)].params.len();
        if list.len() != expected {
            return Err(ModelError::WrongArity { predicate: name, expected, found: list.len() });
        }
        let params = params(&self.domain, &self.names, list)?;
        let args = (0..params.len()).map(|i| Term::Var(i as u8)).collect();
        let head = Literal { positive: true, atom: Atom { predicate: p, args } };
        self.domain.axioms.push(ActionTemplate {
            name,
            vars: params.iter().map(|p| p.ty).collect(),
            params,
            pre: Vec::new(),
            effects: vec![Effect { forall: Vec::new(), when: Vec::new(), literal: head }],
            cost: Vec::new(),
        });
        let action = self.domain.axioms.len() - 1;
        Ok(ActionBuilder { domain: &mut self.domain, names: &self.names, action, axiom: true })
    }

    /// Checks that every action has an effect, that no action changes a derived
    /// predicate and that the rules can be stratified, and returns the domain.
    ///
    /// # Errors
    /// [`ModelError::NoEffects`], [`ModelError::DerivedChanged`],
    /// [`ModelError::NotStratifiable`].
    pub fn build(self) -> Result<Domain, ModelError> {
        if let Some(a) = self.domain.actions.iter().find(|a| a.effects.is_empty()) {
            return Err(ModelError::NoEffects { action: a.name.clone() });
        }
        self.domain.check_derived()?;
        Ok(self.domain)
    }
}

impl ActionBuilder<'_> {
    fn template(&self) -> &ActionTemplate {
        if self.axiom { &self.domain.axioms[self.action] } else { &self.domain.actions[self.action] }
    }

    fn template_mut(&mut self) -> &mut ActionTemplate {
        if self.axiom { &mut self.domain.axioms[self.action] } else { &mut self.domain.actions[self.action] }
    }

    /// The variable of a parameter name (`?x` or `x`), or a constant.
    fn term(&self, arg: &str) -> Result<(Term, TypeId, String), ModelError> {
        let action = self.template();
        let var = check_variable(arg)?;
        if let Some(i) = action.params.iter().position(|p| p.name == var) {
            return Ok((Term::Var(i as u8), action.params[i].ty, format!("?{var}")));
        }
        if !arg.starts_with('?')
            && let Some(c) = self.names.constants.get(&var)
        {
            let ty = self.domain.constants[usize::from(*c)].ty;
            return Ok((Term::Object(*c), ty, var));
        }
        Err(ModelError::UnknownParameter { name: var, action: action.name.clone() })
    }

    fn literal(&self, positive: bool, predicate: &str, args: &[&str]) -> Result<Literal<Term>, ModelError> {
        let terms = args.iter().map(|a| self.term(a)).collect::<Result<Vec<_>, _>>()?;
        let atom = atom_of(self.domain, &NamesRef(self.names), predicate, &terms)?;
        Ok(Literal { positive, atom })
    }

    /// Adds the precondition `predicate(args)` (`args` are parameter names, with or
    /// without `?`, or constants).
    ///
    /// # Errors
    /// [`ModelError::UnknownPredicate`], [`ModelError::WrongArity`],
    /// [`ModelError::UnknownParameter`], [`ModelError::TypeMismatch`].
    pub fn pre(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let l = self.literal(true, predicate, args)?;
        self.template_mut().pre.push(Condition::Literal(l));
        Ok(self)
    }

    /// Adds the negative precondition `not predicate(args)`.
    ///
    /// # Errors
    /// As [`ActionBuilder::pre`].
    pub fn pre_not(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let l = self.literal(false, predicate, args)?;
        self.template_mut().pre.push(Condition::Literal(l));
        Ok(self)
    }

    /// Adds the postcondition `predicate(args)`: the action makes it true.
    ///
    /// # Errors
    /// As [`ActionBuilder::pre`].
    pub fn effect(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let literal = self.literal(true, predicate, args)?;
        self.template_mut().effects.push(Effect { forall: Vec::new(), when: Vec::new(), literal });
        Ok(self)
    }

    /// Adds the postcondition `not predicate(args)`: the action makes it false.
    ///
    /// # Errors
    /// As [`ActionBuilder::pre`].
    pub fn effect_not(&mut self, predicate: &str, args: &[&str]) -> Result<&mut Self, ModelError> {
        let literal = self.literal(false, predicate, args)?;
        self.template_mut().effects.push(Effect { forall: Vec::new(), when: Vec::new(), literal });
        Ok(self)
    }

    /// A new quantified variable of type `ty` for [`Condition::Forall`],
    /// [`Condition::Exists`] or [`Effect::forall`].
    ///
    /// # Errors
    /// [`ModelError::TooManyVariables`] beyond 255 variables.
    pub fn var(&mut self, ty: TypeId) -> Result<Var, ModelError> {
        let a = self.template_mut();
        let index = u8::try_from(a.vars.len()).map_err(|_| ModelError::TooManyVariables { action: a.name.clone() })?;
        a.vars.push(ty);
        Ok(Var { index, ty })
    }

    /// Sets the types of every variable (parameters first), for formulas read with
    /// their own quantified variables.
    pub(crate) fn set_vars(&mut self, types: Vec<TypeId>) {
        self.template_mut().vars = types;
    }

    /// Adds a precondition formula (built with variables of this action; the caller
    /// checks its atoms, as the PDDL reader does).
    pub fn condition(&mut self, c: Condition) -> &mut Self {
        self.template_mut().pre.push(c);
        self
    }

    /// Adds an effect (possibly quantified or conditional).
    pub fn effect_item(&mut self, e: Effect) -> &mut Self {
        self.template_mut().effects.push(e);
        self
    }

    /// Adds a part of the action's cost.
    pub fn cost(&mut self, c: CostTerm) -> &mut Self {
        self.template_mut().cost.push(c);
        self
    }
}

/// Most objects in a problem (constants included): ids are `u16`, and bt-core leaves
/// reserve the two highest values.
pub const MAX_OBJECTS: u16 = u16::MAX - 2;
