//! CGA-like shape grammars (`.sg`) compiled to a genform generator graph.
