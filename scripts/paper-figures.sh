#!/bin/sh
# The ShapeGenetics paper's parameter study (§4.2, Figures 4–9) on
# spaceship_volume with genform sweep. Run from the repository root after
# `cargo build --release`; results go to $OUT (default paper-figures-out).
# Every figure is run for the thesis GA (ga.preset = "thesis") and the
# default (improved) GA.
set -e
G=${G:-target/release/genform}
S=examples/scenes/spaceship_volume.toml
OUT=${OUT:-paper-figures-out}
RUNS=${RUNS:-5}
# The paper's baseline (§4.2): population 50, initial length 10, 50
# generations, elitism 1, roulette + 10-tournament, mutation 30 %,
# cut/grow/alter uniform, 3 crossover retries.
BASE="--set ga.population=50 --set ga.elitism=1 --set ga.initial_length=[10,10] --set ga.mutation_rate=0.3
      --set ga.selection={first=\"roulette\",second={tournament=10}} --set ga.mutation={alter=1,grow=1,cut=1}"
sweep() { # name preset args…
  name=$1; preset=$2; shift 2
  $G sweep $S --runs $RUNS --generations 50 --quiet --out $OUT/$name-$preset --set ga.preset=$preset "$@" > /dev/null
}
for p in thesis default; do
  # Figure 4: selection methods of both parents (roulette, 10-tournament, random).
  sweep fig4-selection $p $(echo $BASE | sed 's/--set ga.selection=[^ ]*//') \
    --set 'ga.selection.first=roulette,{tournament=10},random' --set 'ga.selection.second=roulette,{tournament=10},random'
  # Figure 5: population 10…500 (elitism 1).
  sweep fig5-population $p $(echo $BASE | sed 's/--set ga.population=50//') --set ga.population=10,50,100,200,500
  # Figure 6: mutation probability 0 % (crossover only) … 100 % (mutation only).
  sweep fig6-mutation $p $(echo $BASE | sed 's/--set ga.mutation_rate=0.3//') --set ga.mutation_rate=0,0.25,0.5,0.75,1
  # Figure 7: elitism 0 … 45 of 50 (90 %).
  sweep fig7-elitism $p $(echo $BASE | sed 's/--set ga.elitism=1//') --set ga.elitism=0,1,5,10,15,25,45
  # Figure 8: initial genome length 10 … 99 (max_length 100 is exclusive).
  sweep fig8-initial-length $p $(echo $BASE | sed 's/--set ga.initial_length=\[10,10\]//') \
    --set 'ga.initial_length=[10,10];[25,25];[50,50];[75,75];[99,99]'
  # Figure 9: the baseline against the paper's final parameters
  # (population 200, initial length 20, elitism 30): whole [ga] sections.
  sel='selection={first="roulette",second={tournament=10}},mutation={alter=1,grow=1,cut=1},mutation_rate=0.3'
  $G sweep $S --runs $RUNS --generations 50 --quiet --out $OUT/fig9-final-$p \
    --set "ga={preset=\"$p\",population=50,elitism=1,initial_length=[10,10],$sel};{preset=\"$p\",population=200,elitism=30,initial_length=[20,20],$sel}" > /dev/null
done
