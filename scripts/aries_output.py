"""Where an aries run's output lives (docs/options.md, -output DIR/NAME): DIR/NAME.h5 (mesh: rest geometry,
topology), DIR/NAME.xmf (the XDMF index) and one file per written step, DIR/NAME.steps/NAME_%06d.h5 (positions,
displacement, the -output_fields). The one place the scripts, the tests and the benchmarks take that layout from."""
import glob
import os


def step_file(base, step):
    """The file of output step `step` (it may not exist)."""
    d, n = os.path.dirname(base), os.path.basename(base)
    return os.path.join(d, n + ".steps", "%s_%06d.h5" % (n, step))


def step_files(base):
    """Every step file written, in step order."""
    d, n = os.path.dirname(base), os.path.basename(base)
    return sorted(glob.glob(os.path.join(d, n + ".steps", n + "_*.h5")))


def find_step(base, step=None, tool="aries_output"):
    """The file of `step` (default: the last one written); exits with one error line when there is none."""
    files = step_files(base)
    if not files:
        raise SystemExit("%s: error: no output steps for %s (expected %s)" % (tool, base, step_file(base, 0)))
    path = files[-1] if step is None else step_file(base, step)
    if not os.path.exists(path):
        raise SystemExit("%s: error: no output step %d for %s (%d step files, the last %s)"
                         % (tool, step, base, len(files), os.path.basename(files[-1])))
    return path
