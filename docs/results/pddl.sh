#!/usr/bin/env bash
# Planned and learned trees of the shipped PDDL problems under external agents. For each
# problem, GP (baseline variant, seeds 1-5, 200 generations) learns undisturbed, and
# with --disturb 0.05 on 20 and on 100 training episodes (agents of seed 0). Then the
# planner's tree and every learned tree play the same 1,000 held-out disturbed episodes
# (rate 0.05, agents of seed 1000). Prints a Markdown table row per tree.
#
#   docs/results/pddl.sh [path/to/sim-host] [work folder]
set -euo pipefail
sim=${1:-target/release/sim-host}
work=${2:-pddl-runs}
rate=0.05
episodes=1000
problems=(
  "planner/domains/cube-sphere/domain.pddl planner/domains/cube-sphere/problem.pddl"
  "planner/domains/cube-sphere/domain.pddl planner/domains/cube-sphere/problem-blocked.pddl"
  "planner/domains/blocks/domain.pddl planner/domains/blocks/problem.pddl"
)
play() { # domain problem tree-or-empty -> "reached | mean ticks | nodes | fitness"
  local args=(run --domain "$1" --problem "$2" --disturb "$rate" --disturb-seed 1000 --episodes "$episodes")
  [ -n "$3" ] && args+=(--tree "$3")
  "$sim" "${args[@]}" | awk '
    /^tree/    { for (i = 1; i <= NF; i++) if ($i == "nodes") n = $(i - 1) }
    /^goal/    { r = $4 }
    /^ticks/   { t = $3; sub(",", "", t) }
    /^fitness/ { f = $2 }
    END { printf "%s | %s | %s | %s", r, t, n, f }'
}
echo "| problem | tree | goal reached (of $episodes) | mean ticks | nodes | mean fitness |"
echo "|---|---|---:|---:|---:|---:|"
for p in "${problems[@]}"; do
  read -r domain problem <<<"$p"
  file=$(basename "$(dirname "$problem")")/$(basename "$problem")
  name=$(sed -n 's/.*(problem \([^) ]*\)).*/\1/p' "$problem" | head -1)
  "$sim" learn --domain "$domain" --problem "$problem" --seeds 1..5 --out "$work/plain" --force >/dev/null 2>&1
  for e in 20 100; do
    "$sim" learn --domain "$domain" --problem "$problem" --seeds 1..5 --out "$work/disturbed$e" --force \
      --disturb "$rate" --disturb-seed 0 --disturb-episodes "$e" >/dev/null 2>&1
  done
  echo "| $file | planner | $(play "$domain" "$problem" "") |"
  for group in "plain strips undisturbed" "disturbed20 strips-disturb$rate with_--disturb_$rate,_20_episodes" \
      "disturbed100 strips-disturb$rate with_--disturb_$rate,_100_episodes"; do
    read -r folder world how <<<"$group"
    for seed in 1 2 3 4 5; do
      tree="$work/$folder/$name-baseline-$world-seed$seed/best.bt"
      echo "| $file | learned ${how//_/ }, seed $seed | $(play "$domain" "$problem" "$tree") |"
    done
  done
done
