"""A notebook, cell by cell: simulate the paper's B-RT-R test, fit mu-hat
per cycle with the slope from the spring and from the scan, and compare
with the truth the simulator knows.

    PYTHONPATH=build/python python3 python/examples/fit_simulated_test.py
"""
import numpy as np

import wearscar

# [1] A beech test across the growth rings: 120 cycles at 2 kHz, the
#     sensor noise calibrated to the paper's J, a 512 x 384 scan.
test = wearscar.simulate("B-RT-R", cycles=120, seed=11, scan_cols=512,
                         scan_rows=384, scan_pitch=0.0148)
print(test)
print("P from {:.2f} to {:.2f} N, stroke {:.2f} mm".format(
    test.force.p_n.min(), test.force.p_n.max(), np.ptp(test.force.x_mm)))

# [2] Fuse: mu-hat per cycle with k = (1/S) dP/dx and with the scan's
#     centreline slope; the verdict says whether the wear-scar interaction
#     explains the loops.
result = wearscar.fuse(test.force, test.scan, running_in=40)
print(result)
cycles = result.cycles
truth = np.array(test.truth["mu_per_cycle"])

# [3] Against the truth, after running-in (cycles 41-120).
steady = cycles["cycle"] > 40
error_force = cycles["mu_hat_force"][steady] - truth[steady]
error_scan = cycles["mu_hat_scan"][steady] - truth[steady]
print("mu-hat (k from P):    mean {:.4f}, truth {:.4f}, rms error {:.4f}".format(
    cycles["mu_hat_force"][steady].mean(), truth[steady].mean(),
    np.sqrt(np.mean(error_force ** 2))))
print("mu-hat (k from scan): mean {:.4f}, rms error {:.4f}".format(
    cycles["mu_hat_scan"][steady].mean(), np.sqrt(np.mean(error_scan ** 2))))
print("J {:.3f} (noise floor {:.3f}); verdict: {}".format(
    result.summary["comparison"]["J_force"]["mean"],
    result.summary["comparison"]["J_force_split"]["noise_floor"],
    result.summary["verdict"]["summary"]))
print("wear: {:.3f} mm^3 over {:.3f} m at {:.1f} N: k = {:.3g} mm^3/(N m)".format(
    result.summary["wear"]["volume_mm3"],
    result.summary["wear"]["sliding_distance_m"],
    result.summary["wear"]["normal_load_n"],
    result.summary["wear"]["specific_wear_rate_mm3_per_n_m"]))
