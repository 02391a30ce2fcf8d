//! The block ids Minecraft knows, for the compile-time check of every id a
//! grammar names. The lists come from the npm package `minecraft-data`
//! (`data/README.md`); a grammar cannot know the `--data-version` it will
//! be written with, so an id is known when 1.21.1 (the default) or 1.19.4
//! has it, and an id only 1.19.4 has draws a warning.

use genform_core::BlockState;
use genform_core::diag::{Diagnostic, Span};
use genform_core::expr::did_you_mean;
use std::collections::HashSet;
use std::sync::OnceLock;

/// Minecraft 1.21.1 (DataVersion 3955, the default), sorted.
const BLOCKS_1_21_1: &str = include_str!("../data/blocks-1.21.1.txt");
/// Minecraft 1.19.4 (DataVersion 3337), sorted.
const BLOCKS_1_19_4: &str = include_str!("../data/blocks-1.19.4.txt");

/// Ids 1.19.4 has and 1.21.1 renamed.
const RENAMED: &[(&str, &str)] = &[("grass", "short_grass")];

fn ids(text: &'static str) -> impl Iterator<Item = &'static str> {
    text.lines().map(str::trim).filter(|l| !l.is_empty())
}

fn set(cell: &'static OnceLock<HashSet<&'static str>>, text: &'static str) -> &'static HashSet<&'static str> {
    cell.get_or_init(|| ids(text).collect())
}

/// How well an id (without namespace) is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Known {
    /// A 1.21.1 block.
    Current,
    /// A 1.19.4 block that 1.21.1 no longer has.
    OnlyOld,
    /// Neither.
    Unknown,
}

/// Looks `id` (without namespace) up in both lists.
pub(crate) fn lookup(id: &str) -> Known {
    static CURRENT: OnceLock<HashSet<&'static str>> = OnceLock::new();
    static OLD: OnceLock<HashSet<&'static str>> = OnceLock::new();
    if set(&CURRENT, BLOCKS_1_21_1).contains(id) {
        Known::Current
    } else if set(&OLD, BLOCKS_1_19_4).contains(id) {
        Known::OnlyOld
    } else {
        Known::Unknown
    }
}

/// The 1.21.1 id closest to `id`, if it is a plausible typo (the sorted
/// list keeps ties deterministic).
pub(crate) fn suggestion(id: &str) -> Option<&'static str> {
    did_you_mean(id, ids(BLOCKS_1_21_1))
}

/// Checks the block ids of one grammar; `allow` is the span of its
/// `allow_unknown_blocks;` statement, if any.
pub(crate) struct BlockCheck {
    allow: Option<Span>,
    /// Unknown `minecraft:` ids let through by `allow`, with their first use.
    accepted: Vec<(String, Span)>,
}

impl BlockCheck {
    /// A check; unknown ids are errors unless `allow` is given.
    pub(crate) fn new(allow: Option<Span>) -> BlockCheck {
        BlockCheck { allow, accepted: Vec::new() }
    }

    /// Whether the grammar says `allow_unknown_blocks;`.
    pub(crate) fn allows_unknown(&self) -> bool {
        self.allow.is_some()
    }

    /// Checks the id of `state` (named at `span`). Other namespaces than
    /// `minecraft:` are mods' blocks and pass as they are.
    pub(crate) fn check(&mut self, state: &BlockState, span: Span, out: &mut Vec<Diagnostic>) {
        if !state.name.starts_with("minecraft:") {
            return;
        }
        let id = state.id();
        match lookup(id) {
            Known::Current => {}
            Known::OnlyOld => {
                let mut d = Diagnostic::warning(
                    span,
                    format!("`{id}` is a block of 1.19.4 that 1.21.1 (the default data version) no longer has"),
                );
                if let Some((_, new)) = RENAMED.iter().find(|(old, _)| *old == id) {
                    d = d.with_hint(format!("1.21.1 calls it `{new}`; keep `{id}` only for `--data-version 3337`"));
                }
                out.push(d);
            }
            Known::Unknown if self.allow.is_some() => {
                if !self.accepted.iter().any(|(a, _)| a == id) {
                    self.accepted.push((id.to_string(), span));
                }
            }
            Known::Unknown => {
                let mut d = Diagnostic::error(
                    span,
                    format!("unknown block id `{id}` (not a Minecraft 1.21.1 or 1.19.4 block)"),
                );
                if let Some(s) = suggestion(id) {
                    d = d.with_hint(format!("did you mean `{s}`?"));
                }
                out.push(d.with_hint(
                    "a mod's block needs its namespace (`create:andesite_casing`); `allow_unknown_blocks;` accepts any id",
                ));
            }
        }
    }

    /// One warning naming every unknown id `allow_unknown_blocks` let through.
    pub(crate) fn finish(self, out: &mut Vec<Diagnostic>) {
        let Some(allow) = self.allow else { return };
        if self.accepted.is_empty() {
            return;
        }
        let names: Vec<String> = self.accepted.iter().map(|(n, _)| format!("`{n}`")).collect();
        let mut d = Diagnostic::warning(
            allow,
            format!("`allow_unknown_blocks` lets through ids Minecraft does not know: {}", names.join(", ")),
        );
        for (n, span) in &self.accepted {
            d = d.with_label(*span, format!("`{n}` first used here"));
        }
        out.push(d);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_hold_the_common_blocks_of_both_versions() {
        for id in ["stone", "air", "water", "oak_stairs", "stone_bricks", "cracked_stone_bricks", "grass_block"] {
            assert_eq!(lookup(id), Known::Current, "{id}");
        }
        assert_eq!(lookup("short_grass"), Known::Current);
        assert_eq!(lookup("grass"), Known::OnlyOld);
        assert_eq!(lookup("not_a_block_at_all"), Known::Unknown);
        assert_eq!(lookup(""), Known::Unknown);
    }

    #[test]
    fn typos_get_the_nearest_block() {
        assert_eq!(suggestion("stone_brics"), Some("stone_bricks"));
        assert_eq!(suggestion("oak_plnks"), Some("oak_planks"));
        assert_eq!(suggestion("zzzzzzzzzzzzzzzzzzzz"), None);
    }

    #[test]
    fn mods_pass_and_allow_turns_errors_into_one_warning() {
        let span = Span::new(0, 1);
        let mut out = Vec::new();
        let mut strict = BlockCheck::new(None);
        strict.check(&BlockState::parse("create:andesite_casing").unwrap(), span, &mut out);
        strict.check(&BlockState::parse("oak_stairs[facing=east]").unwrap(), span, &mut out);
        assert!(out.is_empty(), "{out:?}");
        strict.check(&BlockState::parse("minecraft:stone_brics[a=b]").unwrap(), span, &mut out);
        assert_eq!(out.len(), 1);
        assert!(out[0].message.contains("`stone_brics`"), "{}", out[0].message);
        assert!(out[0].hints.iter().any(|h| h.contains("`stone_bricks`")));

        let mut out = Vec::new();
        let mut lax = BlockCheck::new(Some(span));
        for name in ["foo_block", "bar_block", "foo_block"] {
            lax.check(&BlockState::new(name), span, &mut out);
        }
        assert!(out.is_empty());
        lax.finish(&mut out);
        assert_eq!(out.len(), 1);
        assert!(out[0].message.ends_with("`foo_block`, `bar_block`"), "{}", out[0].message);
    }
}
