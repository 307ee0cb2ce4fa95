#!/usr/bin/env python3
"""Bounds for the stress table from many seeds (the method behind kExceptions).

    for s in $(seq 0 59); do build/tests/stress/tessera-stress --seed $s > out/$s.txt; done
    python3 tests/stress/derive_bounds.py out/*.txt

Rows that never erred over all the seeds stay exact (0 wrong, 0 all-hits): a claim that a
decision is always right, which a failure at another seed must make someone look at. Rows
with errors count rare, independent events over their rays, taken as Poisson per seed: with
S events over n seeds, the rate's upper 99.9% confidence limit is the lambda at which
P(Poisson(n lambda) <= S) = 0.001, and the bound is the smallest count k >= the largest seen
with P(Poisson(lambda) > k) <= 1e-5 (with ~40 such rows, about 4e-4 for a new seed to fail
one; a row that never erred can still meet a rarer event at a new seed, and did at 2 of 30
held-out seeds: tests/stress/README.md). t: within 1e-7 (the float rounding of an exact
root is at most 2^-24 = 6e-8) unless some seed measured more, or more than half a wider
bound; then twice the largest error measured, on a 1-2-5 ladder (the measures of
stress_cases.cpp's t_conditioning and start_pair_conditioning keep the rows' spread over
seeds narrow). Prints the rows whose bounds are below the derived
ones, then those above them (kept unless their reason is gone). Standard library only.
"""
import math
import re
import sys

DEFAULT_T = 1e-7
ROUNDING = 2.0**-24 * (1 + 1e-3)  # a double root rounded to float
ROW = re.compile(r"^(.{22}) (.+?) +(\d+) +(\d+) +(\d+) +(\d+) +(\d+) +(\S+) +(\d+)  "
                 r"<=(\d+) / <=(\d+) / <=(\S+) +(ok|FAIL)$")


def poisson_cdf(k, mean):
    """P(X <= k) for X ~ Poisson(mean), summed in log space (large means stay finite)."""
    if mean == 0:
        return 1.0
    total = 0.0
    log_term = -mean
    for i in range(k + 1):
        if i > 0:
            log_term += math.log(mean) - math.log(i)
        total += math.exp(log_term)
    return min(total, 1.0)


def rate_upper_limit(events, seeds, confidence=0.999):
    low, high = 0.0, (events + 10 + 10 * math.sqrt(events + 1)) / seeds
    for _ in range(100):
        mid = (low + high) / 2
        if poisson_cdf(events, seeds * mid) > 1 - confidence:
            low = mid
        else:
            high = mid
    return high


def count_bound(counts, tail=1e-5):
    rate = rate_upper_limit(sum(counts), len(counts))
    k = max(counts)
    while 1 - poisson_cdf(k, rate) > tail:
        k += 1
    return k


def t_bound(worst):
    bound = DEFAULT_T
    ladder = [1, 2, 5]
    exponent = -7
    while bound < 2 * worst:
        for step in ladder:
            bound = step * 10.0 ** exponent
            if bound >= 2 * worst:
                break
        exponent += 1
    return bound


def main(paths):
    rows = {}
    for path in paths:
        with open(path) as f:
            for line in f:
                m = ROW.match(line.rstrip("\n"))
                if not m:
                    continue
                key = (m.group(1).strip(), m.group(2).strip())
                row = rows.setdefault(key, {"wrong": [], "all": [], "t": [], "bounds": None})
                row["wrong"].append(int(m.group(5)))
                row["all"].append(int(m.group(6)))
                row["t"].append(float(m.group(8)))
                row["bounds"] = (int(m.group(10)), int(m.group(11)), float(m.group(12)))
    seeds = max((len(r["wrong"]) for r in rows.values()), default=0)
    looser, tighter = [], []
    for (surface, family), r in rows.items():
        worst_t = max(r["t"])
        derived = (count_bound(r["wrong"]) if any(r["wrong"]) else 0,
                   count_bound(r["all"]) if any(r["all"]) else 0,
                   DEFAULT_T if worst_t <= ROUNDING else t_bound(worst_t))
        now = r["bounds"]
        line = (f"{surface:22} {family:24} {max(r['wrong']):9d} {max(r['all']):7d} "
                f"{worst_t:9.2e}  {now[0]:>6} / {now[1]:>5} / {now[2]:.0e}  "
                f"{derived[0]} / {derived[1]} / {derived[2]:.0e}")
        if (derived[0] > now[0] or derived[1] > now[1] or worst_t > now[2] or
                (now[2] > DEFAULT_T and worst_t > now[2] / 2)):
            looser.append(line)
        elif derived != now and not (now[2] < DEFAULT_T and derived[:2] == now[:2]):
            tighter.append(line)
    header = (f"{'surface':22} {'family':24} {'wrong max':>9} {'all max':>7} {'t max':>9}  "
              f"{'now (wrong / all / t)':>22}  derived")
    print(f"{len(rows)} rows, {seeds} seeds.\nRows whose bounds are below the derived ones:")
    print(header)
    print("\n".join(looser) if looser else "(none)")
    print("\nRows whose bounds are above the derived ones (kept unless their reason is gone):")
    print(header)
    print("\n".join(tighter) if tighter else "(none)")

if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
