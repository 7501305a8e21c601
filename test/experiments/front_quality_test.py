"""experiments/front_quality.py on synthetic fronts: the hypervolume by hand, the common
reference point, the 95 % verdict and the refusal of a file that is not a front.csv."""

import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXP = os.path.join(HERE, "..", "..", "experiments")
sys.path.insert(0, EXP)
import front_quality  # noqa: E402

HEADER = "point,label,training_lap_loss_s,training_stability,base_training_stability\n"


def write(folder, rows):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "front.csv"), "w") as f:
        f.write(HEADER)
        for k, (x, y) in enumerate(rows):
            f.write("%d,p%d,%r,%r,10.0\n" % (k, k, x, y))


def main():
    # By hand: (0, 8) and (0.5, 4) up to (1, 10): 0.5*2 + 0.5*6 = 4; a dominated point adds 0.
    assert front_quality.hypervolume([(0.0, 8.0), (0.5, 4.0), (0.6, 5.0)], (1.0, 10.0)) == 4.0
    assert front_quality.hypervolume([], (1.0, 10.0)) == 0.0
    with tempfile.TemporaryDirectory() as tmp:
        a, b, bad = (os.path.join(tmp, n) for n in ("a", "b", "bad"))
        write(a, [(0.0, 8.0), (0.4, 4.2)])
        write(b, [(0.0, 8.0), (0.4, 4.0), (0.5, 3.9)])
        hv_a, hv_b, ratio, ref = front_quality.quality(front_quality.read_front(a),
                                                       front_quality.read_front(b))
        assert abs(ref[0] - 0.55) < 1e-12 and ref[1] == 10.0, ref
        assert 0.9 < ratio < 1.0 and hv_a < hv_b, (hv_a, hv_b)
        run = lambda *args: subprocess.run([sys.executable, os.path.join(EXP, "front_quality.py")]
                                           + list(args), capture_output=True, text=True)
        ok = run(a, b)
        assert ok.returncode == 0, ok.stdout + ok.stderr
        assert "front / best known 0.9" in ok.stdout, ok.stdout
        # A front that beats the reference is measured against both together: (0.3, 3.0)
        # dominates b's tail, so the best known front is a's and b's points pooled.
        write(a, [(0.0, 8.0), (0.3, 3.0)])
        better = run(a, b)
        assert better.returncode == 0 and "front / best known 1.000" in better.stdout, better.stdout
        # Several reference folders pool their points.
        c = os.path.join(tmp, "c")
        write(c, [(0.0, 7.0)])
        pooled = run(a, b, c)
        assert pooled.returncode == 1, pooled.stdout
        write(a, [(0.0, 8.0), (0.4, 4.2)])
        write(a, [(0.0, 9.0)])
        assert run(a, b).returncode == 1
        os.makedirs(bad)
        with open(os.path.join(bad, "front.csv"), "w") as f:
            f.write("x,y\n1,2\n")
        refused = run(bad, b)
        assert refused.returncode == 2 and "not a front.csv" in refused.stderr, refused.stderr
    print("front_quality: ok")


if __name__ == "__main__":
    main()
