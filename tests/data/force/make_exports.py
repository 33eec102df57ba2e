#!/usr/bin/env python3
"""Writes force exports laid out as the real instruments write them
(FORMATS.md, "Tribometer exports"), over a simple reciprocating test on a
wavy track: x = A sin(2 pi f t), P = 30 N + 0.4 N sin(2 pi x / 1.6 mm) (the
spring S = 10.19 N/mm follows the track), Q the wear-scar force P (k + s mu)
/ (1 - s mu k) with k = (1/S) dP/dx in gross slip and an elastic stick at
the reversals. Run from this folder."""
import math

A, F, MU, K, S = 2.85, 1.0, 0.12, 150.0, 10.19  # mm, Hz, -, N/mm, N/mm


def test(rate, cycles):
    rows, q, x_prev = [], 0.0, None
    for i in range(int(rate * cycles / F)):
        t = i / rate
        x = A * math.sin(2 * math.pi * F * t)
        p = 30.0 + 0.4 * math.sin(2 * math.pi * x / 1.6)
        k = 0.4 * 2 * math.pi / 1.6 * math.cos(2 * math.pi * x / 1.6) / S
        upper = p * (k + MU) / (1 - MU * k)
        lower = p * (k - MU) / (1 + MU * k)
        if x_prev is not None:
            q += K * (x - x_prev)
        q = max(lower, min(upper, q))
        x_prev = x
        rows.append((t, x, q, p))
    return rows


def write(name, text):
    with open(name, 'w', newline='') as f:
        f.write(text)


# Bruker/CETR UMT, from its Data Viewer: a header block of free text and
# "Key = value" lines, blank lines, the names row, a units row with mm/sec,
# sec, g and a trailing comma, a blank line, then data rows ending in a
# comma; forces in gram-force, Fz negative; the block repeats for each step
# and the step's clock T restarts.
G = 9.80665e-3
out = []
rows = test(100, 6)
for step, part in enumerate((rows[:300], rows[300:]), start=1):
    out += ['Created by CETR UMT Data Viewer ver. 1.138.266',
            f'Run # {step}', f'Step No. {step}', 'Velocity     = 240',
            f'Data Count   = {len(part)}',
            'Started at: 3/14/2019 10:12:31 AM', '', '',
            'Fx,Fz,Z,Y,X,V1,V2,T,Ff,COF',
            'g,g,mm,mm,mm,mm/sec,mm/sec,sec,g,', '']
    t0 = part[0][0]
    for t, x, q, p in part:
        out.append(f'{q / G:.3f},{-p / G:.3f},-1.2500,0.0000,{x:.5f},'
                   f'0.000,0.000,{t - t0:.3f},{abs(q) / G:.3f},'
                   f'{abs(q) / p:.4f},')
    out.append('')
write('cetr_umt.csv', '\n'.join(out) + '\n')

# A home-built rig: a misspelt rate line, no time column, the position in
# micrometres under a header with no unit, semicolons.
out = ['Sampling frequncy [Hz]: 200; rig: pin-on-plate v3',
       'x-Position;Friction;Normal']
for t, x, q, p in test(200, 5):
    out.append(f'{1000 * x:.2f};{q:.4f};{p:.4f}')
write('home_built_um.csv', '\n'.join(out) + '\n')

# Quoted header cells holding the delimiter.
out = ['"Time, s","Position, mm","Fx, N","Fz, N"']
for t, x, q, p in test(200, 5):
    out.append(f'{t:.4f},{x:.5f},{q:.4f},{p:.4f}')
write('quoted_header.csv', '\n'.join(out) + '\n')

# Exports that cannot carry the method.
out = ['Time (s),Distance (m),Laps,mu']
for i in range(400):
    out.append(f'{0.05 * i:.2f},{0.0005 * i:.5f},{i // 20},0.31')
write('pin_on_disk.csv', '\n'.join(out) + '\n')
out = ['Recipe: rotary,Operator: lab', 'RecipeStep,Timestamp,DAQ.COF (),'
       'DAQ.Fz (N),Rotary.Speed (rpm),']
for i in range(400):
    out.append(f'1,{0.01 * i:.3f},0.2100,-20.00,60,')
write('rtec_cof_only.csv', '\n'.join(out) + '\n')
