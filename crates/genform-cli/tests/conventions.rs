//! End-to-end tests of the command line's conventions: shell completions,
//! help texts that name every formalism, `sample` saying what it did not
//! write, progress lines when stderr is a pipe.

mod common;

use common::{example, genform, ok, root, s};

#[test]
fn completions_are_printed_for_bash_zsh_and_fish() {
    let tmp = tempfile::tempdir().unwrap();
    for (shell, marker) in [("bash", "complete -F"), ("zsh", "#compdef genform"), ("fish", "complete -c genform")] {
        let out = ok(tmp.path(), &["completions", shell]).stdout();
        assert!(out.contains(marker), "{shell}: {}", &out[..out.len().min(300)]);
        for verb in ["sample", "evolve", "sweep", "map", "completions"] {
            assert!(out.contains(verb), "{shell} completes `{verb}`");
        }
    }
    let err = genform(tmp.path(), &["completions", "tcsh"]).fails().stderr();
    assert!(err.contains("bash") && err.contains("zsh") && err.contains("fish"), "{err}");
}

#[test]
fn sample_and_info_help_name_every_grammar_extension() {
    let tmp = tempfile::tempdir().unwrap();
    for verb in ["sample", "info"] {
        let help = ok(tmp.path(), &[verb, "--help"]).stdout();
        for f in genform_app::formalisms() {
            for ext in f.extensions() {
                assert!(help.contains(ext), "`{verb} --help` omits {ext}:\n{help}");
            }
        }
    }
}

#[test]
fn sample_without_out_says_nothing_was_written_and_how_to_write() {
    let tmp = tempfile::tempdir().unwrap();
    let run = ok(tmp.path(), &["sample", s(&example("spaceship.sg")), "--seed", "3"]);
    assert!(!run.stdout().is_empty(), "the summary is printed");
    let err = run.stderr();
    assert!(err.contains("no model file written") && err.contains("--out spaceship.glb"), "{err}");
    assert_eq!(std::fs::read_dir(tmp.path()).unwrap().count(), 0, "nothing written");
}

#[test]
fn a_piped_run_prints_progress_lines_while_it_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = root().join("examples/scenes/spaceship_volume.toml");
    let args = ["evolve", s(&scene), "--generations", "4", "--threads", "1", "-o", "run", "--set", "ga.population=10"];
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_genform"))
        .current_dir(tmp.path())
        .args(args)
        .env("GENFORM_PROGRESS_EVERY", "0")
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains(" · gen ")).collect();
    assert_eq!(lines.len(), 5, "a line per generation 0..=4 at interval 0:\n{err}");
    assert!(lines[4].contains("gen 4/4 · ") && lines[4].contains(" evaluations · best "), "{}", lines[4]);
    // At the default interval (5 s) a run this short prints only its summary.
    let mut again = args.to_vec();
    again[7] = "run2";
    let quiet = ok(tmp.path(), &again).stderr();
    assert!(!quiet.contains(" · gen "), "{quiet}");
}
