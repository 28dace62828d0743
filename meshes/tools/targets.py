"""Per-cell shape-target keyframes (aries -target_file) for the guided shape-targeting scene (paper Fig. 13).

The bunny's guided performance, in time units of the scene (keyframe times 0 .. 1), from the rest geometry only
(z-up, cell centroids; zeta = normalized height, xi = normalized front-back coordinate):
  t = 0     rest: S_t = I everywhere
  t = 0.25  ears grow: cells with zeta > ~0.7 target a volume-preserving stretch 1.5 along z
  t = 0.5   ears grown, body squashed: the rest target diag(1.15, 1.15, 1 / 1.15^2)
  t = 0.75  ears and body back to rest, the front (xi > ~0.5) stretched 1.3 along x (volume-preserving)
  t = 1     rest again
Blends between regions are smoothstep ramps so neighbouring targets stay compatible."""
import numpy as np


def smoothstep(t):
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def iso_stretch(axis, s):
    """Volume-preserving stretch s along a coordinate axis."""
    d = np.full(3, 1.0 / np.sqrt(s))
    d[axis] = s
    return np.diag(d)


def bunny_guided_keyframes(X, T):
    c = X[T].mean(1)
    lo, hi = X.min(0), X.max(0)
    zeta = (c[:, 2] - lo[2]) / (hi[2] - lo[2])
    xi = (c[:, 0] - lo[0]) / (hi[0] - lo[0])
    ears = smoothstep((zeta - 0.65) / 0.15)
    front = smoothstep((xi - 0.45) / 0.2)
    I = np.eye(3)
    ear_target = iso_stretch(2, 1.5)
    squash = np.diag([1.15, 1.15, 1.0 / 1.15 ** 2])
    front_target = iso_stretch(0, 1.3)
    n = len(T)
    k1 = I + ears[:, None, None] * (ear_target - I)
    k2 = ears[:, None, None] * ear_target + (1.0 - ears)[:, None, None] * squash
    k3 = I + front[:, None, None] * (front_target - I)
    frames = [(0.0, np.broadcast_to(I, (n, 3, 3))), (0.25, k1), (0.5, k2), (0.75, k3),
              (1.0, np.broadcast_to(I, (n, 3, 3)))]
    return frames


def write_keyframes(path, frames, comment_lines=()):
    """aries -target_file: comments, 'cells N keyframes K', then per keyframe 'time t' and N lines
    's11 s22 s33 s12 s23 s13' in the order of the tets in the .msh file."""
    n = len(frames[0][1])
    out = ["# " + c for c in comment_lines]
    out.append("cells %d keyframes %d" % (n, len(frames)))
    for t, S in frames:
        out.append("time %.17g" % t)
        S = np.asarray(S)
        cols = np.stack([S[:, 0, 0], S[:, 1, 1], S[:, 2, 2], S[:, 0, 1], S[:, 1, 2], S[:, 0, 2]], axis=1)
        out += ["%.12g %.12g %.12g %.12g %.12g %.12g" % tuple(r) for r in cols]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
