//! The rewriting step of `genform.lpy` (L-Py files run with CPython): the
//! scan of the string, the choice of candidate rules and the structural
//! matching (predecessor, contexts, new contexts, branches, `%`, `ignore:` /
//! `consider:`) run here; what is Python stays Python: production bodies
//! (through the `apply` callable), value checks (`x == v` compiled to
//! callables) and constant parameters (compared with Python's `!=`).
//!
//! `python/genform/lpy.py`'s `Lsystem._step_py` is the reference this
//! must agree with exactly (`GENFORM_LPY_ENGINE=python` runs it).

use std::collections::HashMap;

use pyo3::prelude::*;
use pyo3::types::{PyList, PyString};

/// Name ids fixed for every rule set: the names the scan itself looks at.
const OPEN: u32 = 0;
const CLOSE: u32 = 1;
const CUT: u32 = 2;
const ANY: u32 = 3;
/// The id of a name no rule mentions: only equality with the names of
/// patterns and filters matters, so all such names can share one id.
const UNKNOWN: u32 = u32::MAX;

/// One module of a rule's pattern (the Python `_Pat`).
struct Pat {
    name: u32,
    /// Per argument: `None` for a variable, the constant otherwise.
    consts: Vec<Option<Py<PyAny>>>,
    /// Per argument: the value check of a variable (`x == v`), if any.
    checks: Vec<Option<Py<PyAny>>>,
    /// Whether a `*args` argument takes the rest.
    star: bool,
}

/// `ignore:` (skipped names) or `consider:` (only these names).
struct Filter {
    ignore: bool,
    /// Per name id: whether the filter names it (ids past the end, and
    /// `UNKNOWN`, are names it does not).
    names: Vec<bool>,
}

impl Filter {
    fn skips(&self, name: u32) -> bool {
        if name == OPEN || name == CLOSE {
            return false;
        }
        self.names.get(name as usize).copied().unwrap_or(false) == self.ignore
    }
}

struct Rule {
    left: Vec<Pat>,
    nleft: Vec<Pat>,
    pred: Vec<Pat>,
    nright: Vec<Pat>,
    right: Vec<Pat>,
    filter: Option<Filter>,
}

/// The active rules of one step (one kind, group and direction), built
/// once from the Python `_Rule`s and kept by `Lsystem` for later steps.
#[pyclass(frozen, module = "genform._genform")]
pub struct LpyRules {
    rules: Vec<Rule>,
    /// Name → id; ids index `by_name`.
    ids: HashMap<String, u32>,
    /// Per name id: the candidate rules in the order `_step_py` tries them.
    by_name: Vec<Vec<usize>>,
    /// The candidates of a name no rule mentions: the `*` rules.
    star: Vec<usize>,
    /// Whether some rule has a new context (`<<`, `>>`): then the ids of
    /// the produced modules are needed too.
    new_context: bool,
}

fn intern(ids: &mut HashMap<String, u32>, name: &str) -> u32 {
    let next = ids.len() as u32;
    *ids.entry(name.to_owned()).or_insert(next)
}

fn pats(ids: &mut HashMap<String, u32>, list: &Bound<'_, PyAny>) -> PyResult<Vec<Pat>> {
    let mut out = Vec::new();
    for p in list.try_iter()? {
        let p = p?;
        let name: String = p.getattr("name")?.extract()?;
        let kinds: Vec<String> = p.getattr("kinds")?.extract()?;
        let values = p.getattr("values")?;
        let checks = p.getattr("checks")?;
        let mut consts = Vec::with_capacity(kinds.len());
        let mut chk = Vec::with_capacity(kinds.len());
        for (j, kind) in kinds.iter().enumerate() {
            consts.push(if kind == "var" { None } else { Some(values.get_item(j)?.unbind()) });
            let c = checks.call_method1("get", (j,))?;
            chk.push(if c.is_none() { None } else { Some(c.unbind()) });
        }
        out.push(Pat { name: intern(ids, &name), consts, checks: chk, star: !p.getattr("star")?.is_none() });
    }
    Ok(out)
}

#[pymethods]
impl LpyRules {
    /// `rules`: `(file_index, left, nleft, pred, nright, right, filter)`
    /// per active rule, in the order `_ruleset` lists them (the active
    /// group, then group 0, file order in each); `file_index` orders a
    /// name's rules among the `*` rules. Patterns are `_Pat`s, the filter
    /// a `_Filter` or None.
    #[new]
    fn new(rules: &Bound<'_, PyAny>) -> PyResult<Self> {
        let mut ids = HashMap::new();
        for (k, n) in ["[", "]", "%", "*"].iter().enumerate() {
            ids.insert((*n).to_owned(), k as u32);
        }
        let mut built = Vec::new();
        let mut order = Vec::new();
        for r in rules.try_iter()? {
            let r = r?;
            order.push(r.get_item(0)?.extract::<usize>()?);
            let f = r.get_item(6)?;
            let filter = if f.is_none() {
                None
            } else {
                let kind: String = f.getattr("kind")?.extract()?;
                let mut names = Vec::new();
                // A set: iterated, not extracted as a sequence.
                for n in f.getattr("names")?.try_iter()? {
                    let id = intern(&mut ids, &n?.extract::<String>()?) as usize;
                    if names.len() <= id {
                        names.resize(id + 1, false);
                    }
                    names[id] = true;
                }
                Some(Filter { ignore: kind == "ignore", names })
            };
            built.push(Rule {
                left: pats(&mut ids, &r.get_item(1)?)?,
                nleft: pats(&mut ids, &r.get_item(2)?)?,
                pred: pats(&mut ids, &r.get_item(3)?)?,
                nright: pats(&mut ids, &r.get_item(4)?)?,
                right: pats(&mut ids, &r.get_item(5)?)?,
                filter,
            });
        }
        if built.iter().any(|r| r.pred.is_empty()) {
            return Err(pyo3::exceptions::PyValueError::new_err("a rule without a predecessor"));
        }
        let mut by_name = vec![Vec::new(); ids.len()];
        for (k, r) in built.iter().enumerate() {
            by_name[r.pred[0].name as usize].push(k);
        }
        let star = by_name[ANY as usize].clone();
        if !star.is_empty() {
            // As `_step_py`: a name's rules and the `*` rules together in
            // file order (a stable sort, so a module named `*` tries each
            // `*` rule twice, as there).
            for cands in by_name.iter_mut() {
                let own = !cands.is_empty();
                cands.extend(&star);
                if own {
                    cands.sort_by_key(|&k| order[k]);
                }
            }
        }
        let new_context = built.iter().any(|r| !r.nleft.is_empty() || !r.nright.is_empty());
        Ok(LpyRules { rules: built, ids, by_name, star, new_context })
    }
}

/// Module names to ids for one step, remembering each name object seen
/// (its address: module names are a few shared strings).
struct Names<'a, 'py> {
    ids: &'a HashMap<String, u32>,
    /// Runs of one name are common (`F F F`, `[ [`): the last name asked.
    last: (usize, u32),
    seen: rustc_hash::FxHashMap<usize, u32>,
    /// Keeps the names in `seen` alive, so that no address is reused.
    keep: Vec<Bound<'py, PyAny>>,
}

impl<'py> Names<'_, 'py> {
    fn id(&mut self, module: &Bound<'py, PyAny>) -> PyResult<u32> {
        let name = module.getattr(pyo3::intern!(module.py(), "name"))?;
        let key = name.as_ptr() as usize;
        if key == self.last.0 {
            return Ok(self.last.1);
        }
        if let Some(&id) = self.seen.get(&key) {
            self.last = (key, id);
            return Ok(id);
        }
        let id = match name.cast::<PyString>() {
            Ok(s) => self.ids.get(s.to_cow()?.as_ref()).copied().unwrap_or(UNKNOWN),
            Err(_) => UNKNOWN,
        };
        self.seen.insert(key, id);
        self.keep.push(name);
        self.last = (key, id);
        Ok(id)
    }
}

/// A sequence of modules with their name ids: the string, the produced
/// string, or the produced string read backwards.
trait Seq<'py> {
    fn len(&self) -> usize;
    fn id(&self, j: usize) -> u32;
    fn module(&self, j: usize) -> &Bound<'py, PyAny>;
}

struct Fwd<'a, 'py> {
    mods: &'a [Bound<'py, PyAny>],
    ids: &'a [u32],
}

impl<'py> Seq<'py> for Fwd<'_, 'py> {
    fn len(&self) -> usize {
        self.ids.len()
    }
    fn id(&self, j: usize) -> u32 {
        self.ids[j]
    }
    fn module(&self, j: usize) -> &Bound<'py, PyAny> {
        &self.mods[j]
    }
}

struct Rev<'a, 'py>(Fwd<'a, 'py>);

impl<'py> Seq<'py> for Rev<'_, 'py> {
    fn len(&self) -> usize {
        self.0.len()
    }
    fn id(&self, j: usize) -> u32 {
        self.0.id(self.0.len() - 1 - j)
    }
    fn module(&self, j: usize) -> &Bound<'py, PyAny> {
        self.0.module(self.0.len() - 1 - j)
    }
}

/// Index of the `]` closing the branch opened at `i` (or the length).
fn end_bracket<'py>(s: &impl Seq<'py>, i: usize) -> usize {
    end_bracket_from(s, i + 1)
}

/// Index of the `]` closing the branch that position `j` is in.
fn end_bracket_from<'py>(s: &impl Seq<'py>, mut j: usize) -> usize {
    let mut depth = 0usize;
    while j < s.len() {
        match s.id(j) {
            OPEN => depth += 1,
            CLOSE if depth == 0 => return j,
            CLOSE => depth -= 1,
            _ => {}
        }
        j += 1;
    }
    s.len()
}

/// Index of the `[` opening the branch that the `]` at `j` closes (0 if none).
fn begin_bracket<'py>(s: &impl Seq<'py>, j: usize) -> usize {
    let mut depth = 0usize;
    for k in (0..j).rev() {
        match s.id(k) {
            CLOSE => depth += 1,
            OPEN if depth == 0 => return k,
            OPEN => depth -= 1,
            _ => {}
        }
    }
    0
}

/// `_Pat.match`: binds the module's parameters into `out`; false if it
/// does not match (value checks and constants are Python's).
fn pat_match<'py>(p: &Pat, m: &Bound<'py, PyAny>, id: u32, out: &mut Vec<Bound<'py, PyAny>>) -> PyResult<bool> {
    let py = m.py();
    let mut vals: Vec<Bound<'py, PyAny>> = Vec::new();
    if p.name == ANY {
        if p.consts.is_empty() && !p.star {
            return Ok(true);
        }
        // `*(n, x, y)`: the first variable is the name.
        vals.push(m.getattr(pyo3::intern!(py, "name"))?);
    } else if id != p.name {
        return Ok(false);
    }
    let args = m.getattr(pyo3::intern!(py, "args"))?;
    match args.cast::<PyList>() {
        Ok(list) => vals.extend(list.iter()),
        Err(_) => {
            for a in args.try_iter()? {
                vals.push(a?);
            }
        }
    }
    let k = p.consts.len();
    if if p.star { vals.len() < k } else { vals.len() != k } {
        return Ok(false);
    }
    for ((v, c), check) in vals.iter().zip(&p.consts).zip(&p.checks) {
        match c {
            None => {
                if let Some(check) = check
                    && !check.bind(py).call1((v,))?.is_truthy()?
                {
                    return Ok(false);
                }
                out.push(v.clone());
            }
            Some(c) => {
                if v.ne(c.bind(py))? {
                    return Ok(false);
                }
            }
        }
    }
    if p.star {
        out.push(PyList::new(py, &vals[k..])?.into_any());
    }
    Ok(true)
}

/// `_left_match`: the patterns from the last backwards, from `j` on,
/// skipping finished branches and branch starts; where the match begins.
fn left_match<'py>(
    s: &impl Seq<'py>,
    j: isize,
    pats: &[Pat],
    filt: Option<&Filter>,
    out: &mut Vec<Bound<'py, PyAny>>,
) -> PyResult<Option<usize>> {
    let mut j = j;
    let mut per: Vec<Vec<Bound<'py, PyAny>>> = Vec::with_capacity(pats.len());
    for p in pats.iter().rev() {
        while j >= 0 {
            let name = s.id(j as usize);
            if name == CLOSE && p.name != CLOSE {
                j = begin_bracket(s, j as usize) as isize - 1;
                continue;
            }
            if (name == OPEN && p.name != OPEN) || filt.is_some_and(|f| f.skips(name)) {
                j -= 1;
                continue;
            }
            break;
        }
        if j < 0 {
            return Ok(None);
        }
        let mut b = Vec::new();
        if !pat_match(p, s.module(j as usize), s.id(j as usize), &mut b)? {
            return Ok(None);
        }
        per.push(b);
        j -= 1;
    }
    for b in per.into_iter().rev() {
        out.extend(b);
    }
    Ok(Some((j + 1) as usize))
}

/// `_right_match`: lateral branches are skipped unless the pattern enters
/// them with `[`; `]` in the pattern skips to the branch's end. Where the
/// match ends.
fn right_match<'py>(
    s: &impl Seq<'py>,
    mut j: usize,
    pats: &[Pat],
    filt: Option<&Filter>,
    out: &mut Vec<Bound<'py, PyAny>>,
) -> PyResult<Option<usize>> {
    let n = s.len();
    for p in pats {
        if p.name == CLOSE {
            j = end_bracket_from(s, j);
            if j >= n {
                return Ok(None);
            }
            j += 1;
            continue;
        }
        while j < n {
            let name = s.id(j);
            if name == OPEN && p.name != OPEN {
                j = end_bracket(s, j) + 1;
                continue;
            }
            if name == CLOSE {
                return Ok(None);
            }
            if filt.is_some_and(|f| f.skips(name)) {
                j += 1;
                continue;
            }
            break;
        }
        if j >= n || !pat_match(p, s.module(j), s.id(j), out)? {
            return Ok(None);
        }
        j += 1;
    }
    Ok(Some(j))
}

/// `_match`: whether the rule matches with its predecessor from `start`,
/// its parameters bound in string order (left context, new left context,
/// predecessor, new right context, right context).
fn rule_match<'py>(
    r: &Rule,
    mods: &Fwd<'_, 'py>,
    out: &Fwd<'_, 'py>,
    start: isize,
    forward: bool,
    args: &mut Vec<Bound<'py, PyAny>>,
) -> PyResult<bool> {
    let k = r.pred.len();
    if start < 0 || start as usize + k > mods.len() {
        return Ok(false);
    }
    let start = start as usize;
    let mut pred_args = Vec::new();
    for (j, p) in r.pred.iter().enumerate() {
        if !pat_match(p, mods.module(start + j), mods.id(start + j), &mut pred_args)? {
            return Ok(false);
        }
    }
    let filt = r.filter.as_ref();
    let mut left_args = Vec::new();
    if !r.left.is_empty() && left_match(mods, start as isize - 1, &r.left, filt, &mut left_args)?.is_none() {
        return Ok(false);
    }
    let mut new_args = Vec::new();
    if forward {
        if !r.nleft.is_empty() && left_match(out, out.len() as isize - 1, &r.nleft, filt, &mut new_args)?.is_none() {
            return Ok(false);
        }
    } else if !r.nright.is_empty() {
        // Going backward `out` is the produced string reversed.
        let rev = Rev(Fwd { mods: out.mods, ids: out.ids });
        if right_match(&rev, 0, &r.nright, filt, &mut new_args)?.is_none() {
            return Ok(false);
        }
    }
    let mut right_args = Vec::new();
    if !r.right.is_empty() && right_match(mods, start + k, &r.right, filt, &mut right_args)?.is_none() {
        return Ok(false);
    }
    args.extend(left_args);
    if forward {
        args.extend(new_args);
        args.extend(pred_args);
    } else {
        args.extend(pred_args);
        args.extend(new_args);
    }
    args.extend(right_args);
    Ok(true)
}

/// One parallel rewriting step of `mods` (a list of `Module`s), forward
/// or backward: at each module the first candidate rule that matches and
/// whose body produces (`apply(rule, args, start, end)` runs the body of
/// the `rule`-th rule given to `LpyRules` with the bound `args`, the
/// predecessor being `mods[start:end]`, and returns its modules or None).
/// Returns the new list and whether some rule applied.
#[pyfunction]
pub fn lpy_step<'py>(
    rules: &Bound<'py, LpyRules>,
    mods: &Bound<'py, PyAny>,
    forward: bool,
    apply: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyList>, bool)> {
    let py = mods.py();
    let rs = rules.get();
    let mods: Vec<Bound<'py, PyAny>> = mods.try_iter()?.collect::<PyResult<_>>()?;
    let mut names = Names { ids: &rs.ids, last: (0, UNKNOWN), seen: Default::default(), keep: Vec::new() };
    let ids: Vec<u32> = mods.iter().map(|m| names.id(m)).collect::<PyResult<_>>()?;
    let string = Fwd { mods: &mods, ids: &ids };
    let n = mods.len();
    let mut out: Vec<Bound<'py, PyAny>> = Vec::with_capacity(n);
    // The produced modules' ids, kept only where a new context reads them.
    let mut out_ids: Vec<u32> = Vec::new();
    let mut matched = false;
    let mut i: isize = if forward { 0 } else { n as isize - 1 };
    while i >= 0 && (i as usize) < n {
        let iu = i as usize;
        if forward && ids[iu] == CUT {
            i = end_bracket(&string, iu) as isize;
            continue;
        }
        let cands: &[usize] = rs.by_name.get(ids[iu] as usize).unwrap_or(&rs.star);
        let mut done = None;
        for &ri in cands {
            let r = &rs.rules[ri];
            let start = if forward { i } else { i - r.pred.len() as isize + 1 };
            let mut args = Vec::new();
            let produced = Fwd { mods: &out, ids: &out_ids };
            if !rule_match(r, &string, &produced, start, forward, &mut args)? {
                continue;
            }
            let end = start + r.pred.len() as isize;
            let res = apply.call1((ri, PyList::new(py, args)?, start, end))?;
            if !res.is_none() {
                done = Some((res, if forward { end } else { start - 1 }));
                break;
            }
        }
        match done {
            None => {
                if rs.new_context {
                    out_ids.push(ids[iu]);
                }
                out.push(mods[iu].clone());
                i += if forward { 1 } else { -1 };
            }
            Some((res, after)) => {
                let produced: Vec<Bound<'py, PyAny>> = res.try_iter()?.collect::<PyResult<_>>()?;
                let at = out.len();
                if forward {
                    out.extend(produced);
                } else {
                    out.extend(produced.into_iter().rev());
                }
                if rs.new_context {
                    for m in &out[at..] {
                        out_ids.push(names.id(m)?);
                    }
                }
                i = after;
                matched = true;
            }
        }
    }
    if !forward {
        out.reverse();
    }
    Ok((PyList::new(py, out)?, matched))
}
