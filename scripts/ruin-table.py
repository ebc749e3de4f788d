#!/usr/bin/env python3
"""Ruin measures and energy-ledger figures of run folders, as one Markdown table
(docs/ruin-numerics.md). Usage: python3 scripts/ruin-table.py RUN_DIR...

Body distance beyond the footprint: the horizontal distance of a body's centre
(ruins.csv) outside the plan AABB of the undeformed active bodies (bodies.csv centres
± their plan half extents turned by the pose, as summary.json's original footprint),
0 inside; its 50th / 90th / 100th percentile over the active bodies (nearest rank).
"""
import csv, json, math, sys


def percentile(xs, p):
    xs = sorted(xs)
    k = max(0, min(len(xs) - 1, math.ceil(p / 100 * len(xs)) - 1))
    return xs[k]


rows = []
for d in sys.argv[1:]:
    s = json.load(open(d + '/summary.json'))
    ru = s['ruins']
    fx, fy = ru['original_footprint_m']['x'], ru['original_footprint_m']['y']
    passive = {b['name'] for b in csv.DictReader(open(d + '/bodies.csv')) if b['passive'] == '1'}
    dist = []
    for r in csv.DictReader(open(d + '/ruins.csv')):
        if r['name'] in passive:
            continue
        x, y = float(r['x']), float(r['y'])
        dx = max(fx[0] - x, 0.0, x - fx[1])
        dy = max(fy[0] - y, 0.0, y - fy[1])
        dist.append(math.hypot(dx, dy))
    rs = s.get('ruin_stage', {})
    e = rs.get('energy', {})
    offs = [f['horizontal_offset_m'] for f in ru['floors']]
    ovl = [o['overlap_ratio'] for o in ru['slab_overlap']]
    rows.append([
        d.rstrip('/').split('/')[-1],
        rs.get('stop', '-'), '%.2f' % rs.get('end_s', 0.0),
        ' / '.join('%.2f' % o for o in offs),
        ' / '.join('%.2f' % o for o in ovl),
        '%.2f' % ru['debris_footprint_area_m2'],
        '%.2f' % percentile(dist, 50), '%.2f' % percentile(dist, 90), '%.2f' % percentile(dist, 100),
        '%.2f' % ru['max_debris_height_m'],
        '%.1f' % e.get('speed', {}).get('max_mps', float('nan')),
        '%.1e' % e.get('settle_phase', {}).get('max_rise_ratio', float('nan')),
        '%.1f' % (e.get('injected_j', float('nan')) / 1000),
        str(len(rs.get('unsettled_bodies', []))),
    ])
head = ['run', 'stop', 'end s', 'floor offsets m (1/2/3)', 'slab overlap (1-2/2-3)', 'debris area m²',
        'd50 m', 'd90 m', 'd100 m', 'max height m', 'max speed m/s', 'settle rise / V0',
        'injected kJ', 'unsettled']
print('| ' + ' | '.join(head) + ' |')
print('|' + '---|' * len(head))
for r in rows:
    print('| ' + ' | '.join(r) + ' |')
