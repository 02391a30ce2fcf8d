//! Writers for genform Scenes.
