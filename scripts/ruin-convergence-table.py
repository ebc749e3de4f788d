#!/usr/bin/env python3
"""The tables of scripts/ruin-convergence.sh (docs/ruin-numerics.md, "Convergence").

Usage: python3 scripts/ruin-convergence-table.py OUT[,OUT2...] MODE...

Several OUT folders, comma-separated (e.g. the script's runs with SEED=1 and SEED=2),
pool their ensembles: every member of the first, the perturbed members of the others
(their member 0 is the same unperturbed run); single variant runs come from the first.

Per mode it reads OUT/MODE-ensemble/member-NNN/ (the ensemble at the default substep,
member 0 unperturbed) and the variant runs OUT/MODE-sps400-it100, -sps800-it100,
-sps200-it200, and prints (Markdown):

* the ensemble spread of every ruin measure: mean ± sample standard deviation, min–max,
  and the spread s = max − min;
* the convergence table: each variant's value and whether it agrees with the unperturbed
  run x0 (member 0): |x − x0| ≤ max(tol, s), tol = 0.1·|x0| for lengths and areas, 0.1 for
  the slab-overlap ratios (the criterion: "within 10 % (0.1 for ratios) or within the
  ensemble spread, whichever is larger"). A second count says how many measures of each
  variant lie inside the ensemble's range widened by the same tolerance,
  [min − tol, max + tol] (the variant is indistinguishable from a member).

With VARIANT_ENSEMBLE (OUT/MODE-sps400-it100-ens etc., ensembles of the variants, same
seed) a third table compares the distributions: a variant agrees on a measure when its
ensemble mean differs from the reference ensemble's mean by at most max(tol, s), tol now
10 % of the reference mean, s the reference spread; the Welch statistic
t = Δmean / √(sd₀²/n₀ + sd₁²/n₁) is printed beside it (|t| > 2.1 — about 5 % two-sided for
two ensembles of 8 — marks a shift of the mean that the ensembles resolve, whether or not
it is inside the tolerance).

The measures are those of scripts/ruin-table.py: floor-centroid offsets, slab overlap
ratios of consecutive floors, debris footprint area, the 50th / 90th / 100th percentile of
the body-centre distance beyond the original footprint, the maximum debris height.
"""
import csv, glob, json, math, os, statistics, sys


def percentile(xs, p):
    xs = sorted(xs)
    k = max(0, min(len(xs) - 1, math.ceil(p / 100 * len(xs)) - 1))
    return xs[k]


def measures(d):
    """Ruin measures of run folder d, as (name, value, is_ratio), plus run facts."""
    s = json.load(open(os.path.join(d, 'summary.json')))
    ru = s['ruins']
    fx, fy = ru['original_footprint_m']['x'], ru['original_footprint_m']['y']
    passive = {b['name'] for b in csv.DictReader(open(os.path.join(d, 'bodies.csv')))
               if b['passive'] == '1'}
    dist = []
    for r in csv.DictReader(open(os.path.join(d, 'ruins.csv'))):
        if r['name'] in passive:
            continue
        x, y = float(r['x']), float(r['y'])
        dist.append(math.hypot(max(fx[0] - x, 0.0, x - fx[1]), max(fy[0] - y, 0.0, y - fy[1])))
    m = []
    for i, f in enumerate(ru['floors']):
        m.append(('floor %d offset m' % (i + 1), f['horizontal_offset_m'], False))
    for o in ru['slab_overlap']:
        m.append(('slab overlap %s' % '–'.join(str(x) for x in o['floors']), o['overlap_ratio'], True))
    m.append(('debris area m²', ru['debris_footprint_area_m2'], False))
    for p in (50, 90, 100):
        m.append(('d%d m' % p, percentile(dist, p), False))
    m.append(('max debris height m', ru['max_debris_height_m'], False))
    rs = s.get('ruin_stage', {})
    e = rs.get('energy', {})
    facts = {
        'stop': rs.get('stop', '-'), 'end': rs.get('end_s', float('nan')),
        'speed': e.get('speed', {}).get('max_mps', float('nan')),
        'speed_ok': bool(e.get('speed', {}).get('ok', False)),
        'rise': e.get('settle_phase', {}).get('max_rise_ratio', float('nan')),
        'injected': e.get('injected_j', float('nan')) / 1000,
        'unsettled': len(rs.get('unsettled_bodies', [])),
    }
    return m, facts


def fmt(x):
    return '%.2f' % x


def pooled(outs, name):
    """The member folders of ensemble `name` pooled over the OUT folders (module docs)."""
    dirs = []
    for k, out in enumerate(outs):
        mem = sorted(glob.glob(os.path.join(out, name, 'member-*')))
        dirs += mem if k == 0 else [m for m in mem if not m.endswith('member-000')]
    return dirs


def main():
    outs, modes = sys.argv[1].split(','), sys.argv[2:]
    out = outs[0]
    for mode in modes:
        members = pooled(outs, mode + '-ensemble')
        if not members:
            print('no ensemble for %s in %s' % (mode, out))
            continue
        ms = [measures(d) for d in members]
        names = [n for n, _, _ in ms[0][0]]
        ratio = {n: r for n, _, r in ms[0][0]}
        vals = {n: [dict((k, v) for k, v, _ in m[0])[n] for m in ms] for n in names}
        print('### %s: ensemble of %d members (200 substeps/s, 100 iterations)\n' % (mode, len(ms)))
        print('| measure | member 0 | mean ± std | min–max | spread s |')
        print('|---|---|---|---|---|')
        spread = {}
        for n in names:
            v = vals[n]
            spread[n] = max(v) - min(v)
            sd = statistics.stdev(v) if len(v) > 1 else 0.0
            print('| %s | %s | %s ± %s | %s–%s | %s |' % (
                n, fmt(v[0]), fmt(statistics.mean(v)), fmt(sd), fmt(min(v)), fmt(max(v)), fmt(spread[n])))
        f = [m[1] for m in ms]
        print('\nMembers: stop %s; end %s s; max speed %s m/s; unsettled bodies %s; '
              'settle rise / V0 ≤ %.1e; injected %s kJ.\n' % (
                  ', '.join(x['stop'] for x in f), ', '.join('%.2f' % x['end'] for x in f),
                  ', '.join('%.1f' % x['speed'] for x in f), ', '.join(str(x['unsettled']) for x in f),
                  max(x['rise'] for x in f), ', '.join('%.1f' % x['injected'] for x in f)))
        variants = []
        for v in ('sps400-it100', 'sps800-it100', 'sps200-it200'):
            d = os.path.join(out, '%s-%s' % (mode, v))
            if os.path.isfile(os.path.join(d, 'summary.json')):
                variants.append((v, measures(d)))
        print('### %s: convergence (reference: member 0 = sps200-it100)\n' % mode)
        head = ['measure', 'sps200-it100', 'allowed ±'] + [v for v, _ in variants]
        print('| ' + ' | '.join(head) + ' |')
        print('|' + '---|' * len(head))
        passed = {v: 0 for v, _ in variants}
        inside = {v: 0 for v, _ in variants}
        for n in names:
            x0 = vals[n][0]
            tol = 0.1 if ratio[n] else 0.1 * abs(x0)
            allowed = max(tol, spread[n])
            row = [n, fmt(x0), fmt(allowed) + (' (s)' if spread[n] > tol else (' (0.1)' if ratio[n] else ' (10 %)'))]
            for v, (m, _) in variants:
                x = dict((k, y) for k, y, _ in m)[n]
                ok = abs(x - x0) <= allowed + 1e-12
                passed[v] += ok
                inside[v] += min(vals[n]) - tol - 1e-12 <= x <= max(vals[n]) + tol + 1e-12
                row.append('%s %s' % (fmt(x), '✓' if ok else '✗'))
            print('| ' + ' | '.join(row) + ' |')
        print('| runs: stop, end s, max speed, unsettled, injected kJ | %s %.2f, %.1f, %d, %.1f | | %s |' % (
            f[0]['stop'], f[0]['end'], f[0]['speed'], f[0]['unsettled'], f[0]['injected'],
            ' | '.join('%s %.2f, %.1f, %d, %.1f' % (x['stop'], x['end'], x['speed'], x['unsettled'], x['injected'])
                       for _, (_, x) in variants)))
        print('\nAgreeing measures (|x − x0| ≤ max(tol, s)): ' + ', '.join('%s %d/%d' % (v, passed[v], len(names)) for v, _ in variants) + '; inside the ensemble range ± tol: ' + ', '.join('%s %d/%d' % (v, inside[v], len(names)) for v, _ in variants) + '\n')

        ens = []
        for v in ('sps400-it100', 'sps800-it100', 'sps200-it200'):
            mem = pooled(outs, '%s-%s-ens' % (mode, v))
            if mem:
                ens.append((v, [measures(d) for d in mem]))
        if ens:
            distributions(mode, names, ratio, vals, spread, f, ens)


def welch(a, b):
    """Welch's t of the difference of the means of samples a and b (0 if both constant)."""
    se = math.sqrt(statistics.variance(a) / len(a) + statistics.variance(b) / len(b))
    d = statistics.mean(b) - statistics.mean(a)
    return d / se if se > 0 else (0.0 if d == 0 else math.inf)


def run_facts(f):
    """One line on the runs' facts `f` (stop, speed bound, fastest piece, injection)."""
    rest = sum(x['stop'] == 'at_rest' for x in f)
    return '%d/%d at rest, speed bound %d/%d, fastest %.1f–%.1f m/s, injected %.1f kJ mean' % (
        rest, len(f), sum(x['speed_ok'] for x in f), len(f), min(x['speed'] for x in f), max(x['speed'] for x in f),
        statistics.mean(x['injected'] for x in f))


def distributions(mode, names, ratio, vals, spread, f0, ens):
    """The third table: every setting an ensemble (module docs)."""
    print('### %s: convergence of the distributions (an ensemble at every setting)\n' % mode)
    head = ['measure', 'sps200-it100 mean ± std', 'allowed ±'] + ['%s mean ± std (t)' % v for v, _ in ens]
    print('| ' + ' | '.join(head) + ' |')
    print('|' + '---|' * len(head))
    passed = {v: 0 for v, _ in ens}
    shifted = {v: 0 for v, _ in ens}
    for n in names:
        a = vals[n]
        mu0 = statistics.mean(a)
        tol = 0.1 if ratio[n] else 0.1 * abs(mu0)
        allowed = max(tol, spread[n])
        row = [n, '%s ± %s' % (fmt(mu0), fmt(statistics.stdev(a))),
               fmt(allowed) + (' (s)' if spread[n] > tol else (' (0.1)' if ratio[n] else ' (10 %)'))]
        for v, ms in ens:
            b = [dict((k, y) for k, y, _ in m[0])[n] for m in ms]
            ok = abs(statistics.mean(b) - mu0) <= allowed + 1e-12
            t = welch(a, b)
            passed[v] += ok
            shifted[v] += abs(t) > 2.1
            row.append('%s ± %s (%+.1f) %s' % (fmt(statistics.mean(b)), fmt(statistics.stdev(b)), t, '✓' if ok else '✗'))
        print('| ' + ' | '.join(row) + ' |')
    print()
    print('* sps200-it100: ' + run_facts(f0))
    for v, ms in ens:
        print('* %s: %s' % (v, run_facts([m[1] for m in ms])))
    print('\nAgreeing means (|Δmean| ≤ max(tol, s)): ' + ', '.join(
        '%s %d/%d' % (v, passed[v], len(names)) for v, _ in ens) + '; means shifted beyond the ensembles\' '
        'resolution (|t| > 2.1): ' + ', '.join('%s %d/%d' % (v, shifted[v], len(names)) for v, _ in ens) + '\n')


if __name__ == '__main__':
    main()
