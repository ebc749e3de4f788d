#!/usr/bin/env python3
"""The doubling table of scripts/ruin-convergence.sh (docs/ruin-convergence.md).

Usage: python3 scripts/ruin-convergence-doubling.py OUT[,OUT2...] MODE...

Several OUT folders, comma-separated (the script's runs with SEED=1 and SEED=2), pool
each ensemble's members as scripts/ruin-convergence-table.py does: every member of the
first, the perturbed members of the others (member 0 is the same unperturbed run in
every seed); the wall time per member is the pooled folders' wall times over their members.

Reads, per mode, the reference ensemble OUT/MODE-ensemble (200 substeps/s, 100
iterations) and every variant ensemble OUT/MODE-spsS-itI[-KEY-VALUE...]-ens, and gives
each its Gauss–Seidel sweeps per simulated second, S·I. It prints:

* per ensemble: the members, the wall time per member (the ensemble's wall time that
  scripts/ruin-convergence.sh wrote to OUT/NAME.wall_s, divided by the members: the time
  of one run when the ensemble ran on one worker thread) and every measure's mean ±
  sample standard deviation;
* the doubling table: for every pair of plain ensembles (no extra keys) whose sweeps per
  second differ by a factor of two, and for every ensemble with extra keys against the
  plain one of the same sweeps, whether each ensemble mean moved by more than the
  criterion allows,

      |mean_B − mean_A| ≤ max(0.05·|mean_A|, sd_A / 2)

  (A the coarser or plain ensemble, sd_A its sample standard deviation). A setting is
  converged when the pair (it, its doubling) moves no mean beyond that. Beside each
  difference stands Welch's t (scripts/ruin-convergence-table.py); the table counts the
  moves the ensembles resolve (|t| > 2.1) and prints the standard error of a difference of
  two means in units of the spread, √(1/n_A + 1/n_B) (equal spreads): with 8 members each
  it is 0.5, as large as the criterion's sd_A / 2, so a mean can fail the criterion by
  sampling alone; resolving it needs about 4·√(2/n) ≤ 1, n ≥ 32 members per ensemble.

The measures are those of scripts/ruin-convergence-table.py (floor offsets, slab
overlaps, debris area, percentiles of the distance beyond the footprint, debris height),
with the floors' vertical drops (the z of each floor's centroid displacement) and, where
the members' summary.json holds a `rescue` section (written by `fem2rbd run`, rewritten by
`fem2rbd voids`), the rescue measures: the number of voids, of survivable voids, and the
survivable volume (m³).
"""
import glob, importlib.util, json, math, os, re, statistics, sys

spec = importlib.util.spec_from_file_location(
    'table', os.path.join(os.path.dirname(os.path.abspath(__file__)), 'ruin-convergence-table.py'))
table = importlib.util.module_from_spec(spec)
spec.loader.exec_module(table)


def member_measures(d):
    m, facts = table.measures(d)
    s = json.load(open(os.path.join(d, 'summary.json')))
    for i, f in enumerate(s['ruins']['floors']):
        m.append(('floor %d drop m' % (i + 1), -f['centroid_displacement_m'][2], False))
    r = s.get('rescue')
    if r:
        m.append(('voids', float(r['voids_count']), False))
        m.append(('survivable voids', float(r['survivable_count']), False))
        m.append(('survivable volume m³', r['survivable_volume_m3'], False))
    return dict((n, v) for n, v, _ in m), [n for n, _, _ in m], facts


def ensemble(outs, name):
    mem = table.pooled(outs, name)
    if not mem:
        return None
    ms = [member_measures(d) for d in mem]
    names = [n for n in ms[0][1] if all(n in m[0] for m in ms)]
    vals = {n: [m[0][n] for m in ms] for n in names}
    wall_s, counted = 0.0, 0
    for out in outs:
        wall_file = os.path.join(out, name) + '.wall_s'
        if os.path.isfile(wall_file):
            wall_s += float(open(wall_file).read())
            counted += len(glob.glob(os.path.join(out, name, 'member-*')))
    wall = wall_s / counted if counted else float('nan')
    return {'n': len(ms), 'names': names, 'vals': vals, 'wall': wall, 'facts': [m[2] for m in ms]}


def main():
    outs, modes = sys.argv[1].split(','), sys.argv[2:]
    out = outs[0]
    for mode in modes:
        ens = {}
        ref = ensemble(outs, mode + '-ensemble')
        if ref:
            ens[(200, 100, '')] = ref
        for d in sorted(glob.glob(os.path.join(out, mode + '-sps*-ens'))):
            m = re.match(r'sps(\d+)-it(\d+)(-.*)?-ens$', os.path.basename(d)[len(mode) + 1:])
            e = ensemble(outs, os.path.basename(d)) if m else None
            if e:
                ens[(int(m.group(1)), int(m.group(2)), (m.group(3) or '')[1:])] = e
        if not ens:
            print('no ensembles for %s in %s' % (mode, out))
            continue
        keys = sorted(ens, key=lambda k: (k[0] * k[1], k[2], k[0]))
        names = [n for n in ens[keys[0]]['names'] if all(n in ens[k]['vals'] for k in keys)]
        label = lambda k: '%d/%d%s' % (k[0], k[1], (' ' + k[2]) if k[2] else '')
        print('### %s: ensembles (substeps/s / iterations, sweeps/s)\n' % mode)
        print('| measure | ' + ' | '.join('%s (%d k)' % (label(k), k[0] * k[1] // 1000) for k in keys) + ' |')
        print('|---|' + '---|' * len(keys))
        print('| members | ' + ' | '.join(str(ens[k]['n']) for k in keys) + ' |')
        print('| wall s per member | ' + ' | '.join('%.0f' % ens[k]['wall'] for k in keys) + ' |')
        for n in names:
            print('| %s | ' % n + ' | '.join(
                '%.2f ± %.2f' % (statistics.mean(ens[k]['vals'][n]), statistics.stdev(ens[k]['vals'][n]))
                for k in keys) + ' |')
        print('| at rest | ' + ' | '.join(
            '%d/%d' % (sum(f['stop'] == 'at_rest' for f in ens[k]['facts']), ens[k]['n']) for k in keys) + ' |')
        print('| injected kJ, mean | ' + ' | '.join(
            '%.1f' % statistics.mean(f['injected'] for f in ens[k]['facts']) for k in keys) + ' |')
        print()
        pairs = []
        for a in keys:
            for b in keys:
                plain = a[2] == '' and b[2] == '' and b[0] * b[1] == 2 * a[0] * a[1]
                switch = a[2] == '' and b[2] != '' and b[0] * b[1] == a[0] * a[1] and b[:2] == a[:2]
                if plain or switch:
                    pairs.append((a, b))
        if not pairs:
            continue
        print('### %s: doubling table (|Δmean| ≤ max(5 %% of mean_A, sd_A / 2))\n' % mode)
        print('| measure | ' + ' | '.join('%s → %s' % (label(a), label(b)) for a, b in pairs) + ' |')
        print('|---|' + '---|' * len(pairs))
        moved = {p: [] for p in pairs}
        for n in names:
            row = []
            for a, b in pairs:
                va, vb = ens[a]['vals'][n], ens[b]['vals'][n]
                ma, mb, sa = statistics.mean(va), statistics.mean(vb), statistics.stdev(va)
                allowed = max(0.05 * abs(ma), 0.5 * sa)
                ok = abs(mb - ma) <= allowed + 1e-12
                if not ok:
                    moved[(a, b)].append(n)
                t = table.welch(va, vb)
                row.append('%+.2f (±%.2f, t %+.1f) %s' % (mb - ma, allowed, t, '✓' if ok else '✗'))
            print('| %s | ' % n + ' | '.join(row) + ' |')
        print('| means moved | ' + ' | '.join('%d of %d' % (len(moved[p]), len(names)) for p in pairs) + ' |')
        print('| of them resolved, abs(t) > 2.1 | ' + ' | '.join(
            '%d' % sum(abs(table.welch(ens[a]['vals'][n], ens[b]['vals'][n])) > 2.1 for n in moved[(a, b)])
            for a, b in pairs) + ' |')
        print('| standard error of a difference of means / sd_A | ' + ' | '.join(
            '%.2f' % math.sqrt(1 / ens[a]['n'] + 1 / ens[b]['n']) for a, b in pairs) + ' |')
        print()


if __name__ == '__main__':
    main()
