"""A video's quality against an analytic truth, panoproj against FFmpeg's v360 (issue 47):

    scripts/bench.sh video-quality

An analytic scene (luma: waves up to 0.4 cycles a source pixel, above the output's Nyquist
limit; chroma: waves below its output's limit) is rendered per frame into a 1536x768 equirect, 4:2:0 with chroma
sited left (as H.264's), encoded losslessly (FFV1); each tool shrinks it 3x to a 512x256 equirect
turned by 17.3 degrees of yaw and 5 of pitch, encoded losslessly again. The truth is the scene
averaged over each output pixel (8x8 points); chroma's truth is the same at its sited places.
The chroma carries waves up to 0.1 cycles a source chroma pixel. Reported: luma PSNR against the truth for panoproj (antialiasing auto, bicubic) and v360 (line,
cubic), and the chroma's RMS error in LSB.
"""
import pathlib
import subprocess
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
CLI = ROOT / "build-bench" / "tools" / "panoproj"
SW, SH, OW, OH, FRAMES = 1536, 768, 512, 256, 4
YAW, PITCH = 17.3, 5.0


def rays_equirect(x, y, w, h):
    lon = (x / w - 0.5) * 2 * np.pi
    lat = (0.5 - y / h) * np.pi
    return np.stack([np.cos(lat) * np.sin(lon), np.sin(lat), np.cos(lat) * np.cos(lon)], -1)


WAVES = np.random.default_rng(3).normal(size=(24, 3))
WAVES /= np.linalg.norm(WAVES, axis=1, keepdims=True)
FREQ = np.random.default_rng(4).uniform(0.1, 0.4, 24) * SW  # radians of phase per radian
PHASE = np.random.default_rng(5).uniform(0, 2 * np.pi, 24)
# Chroma's detail: up to 0.1 cycles a source chroma pixel (below the output chroma's Nyquist limit,
# 1/6: its error is the kernel's and the siting's, not aliasing).
CFREQ = np.random.default_rng(6).uniform(0.03, 0.1, 16) * SW / 2


def scene(d, frame):
    """Y, Cb, Cr in 8-bit video levels at unit rays d (frames differ by a phase)."""
    y = np.full(d.shape[:-1], 126.0)
    for k in range(24):
        y += 4.0 * np.cos(FREQ[k] * (d @ WAVES[k]) + PHASE[k] + 0.7 * frame)
    cb = 128 + 20 * d[..., 0] * np.cos(3 * d[..., 1] + frame)
    cr = 128 + 20 * d[..., 2] * np.sin(2 * d[..., 0] - frame)
    for k in range(16):
        wave = 5.0 * np.cos(CFREQ[k] * (d @ WAVES[k]) + PHASE[k] + 0.5 * frame)
        if k % 2:
            cb += wave
        else:
            cr += wave
    return np.clip(y, 16, 235), np.clip(cb, 16, 240), np.clip(cr, 16, 240)


def rotation(yaw, pitch):
    """panoproj's: the output ray turned by R is the source's (yaw about +Y, then pitch)."""
    a, b = np.radians(yaw), np.radians(pitch)
    ry = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    rx = np.array([[1, 0, 0], [0, np.cos(b), np.sin(b)], [0, -np.sin(b), np.cos(b)]])
    return ry @ rx


def source(work):
    raw = work / "src.yuv"
    with open(raw, "wb") as f:
        for fr in range(FRAMES):
            yy, xx = np.mgrid[0:SH, 0:SW] + 0.5
            y, _, _ = scene(rays_equirect(xx, yy, SW, SH), fr)
            cy, cx = np.mgrid[0:SH // 2, 0:SW // 2]
            _, cb, cr = scene(rays_equirect(2 * cx + 0.5, 2 * cy + 1.0, SW, SH), fr)  # left-sited
            for p in (y, cb, cr):
                f.write(np.round(p).astype(np.uint8).tobytes())
    out = work / "src.mkv"
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "yuv420p", "-s", f"{SW}x{SH}", "-r", "10",
                    "-i", str(raw), "-c:v", "ffv1", "-chroma_sample_location", "left", str(out)], check=True)
    return out


def truth(fr, r, n=8):
    """The scene averaged over each output pixel (n x n points), luma and sited chroma."""
    def at(xs, ys):
        d = rays_equirect(xs, ys, OW, OH) @ r.T
        return scene(d, fr)
    acc = [np.zeros((OH, OW)), np.zeros((OH // 2, OW // 2)), np.zeros((OH // 2, OW // 2))]
    yy, xx = np.mgrid[0:OH, 0:OW].astype(float)
    cy, cx = np.mgrid[0:OH // 2, 0:OW // 2].astype(float)
    for i in range(n):
        for j in range(n):
            o = ((i + 0.5) / n, (j + 0.5) / n)
            acc[0] += at(xx + o[0], yy + o[1])[0]
            # a chroma pixel spans 2x2 luma pixels around its sited place (2i + 0.5, 2j + 1)
            _, cb, cr = at(2 * cx - 0.5 + 2 * o[0], 2 * cy + 2 * o[1])
            acc[1] += cb
            acc[2] += cr
    return [a / (n * n) for a in acc]


def planes(file, work):
    raw = work / "out.yuv"
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", str(file), "-vsync", "0", "-f", "rawvideo", "-pix_fmt", "yuv420p",
                    str(raw)], check=True)
    data = np.fromfile(raw, np.uint8)
    n = OW * OH
    frames = []
    for f in range(len(data) // (n * 3 // 2)):
        d = data[f * n * 3 // 2:(f + 1) * n * 3 // 2].astype(float)
        frames.append([d[:n].reshape(OH, OW), d[n:n + n // 4].reshape(OH // 2, OW // 2),
                       d[n + n // 4:].reshape(OH // 2, OW // 2)])
    return frames


def main():
    with tempfile.TemporaryDirectory() as t:
        work = pathlib.Path(t)
        src = source(work)
        r = rotation(YAW, PITCH)
        truths = [truth(fr, r) for fr in range(FRAMES)]
        outs = {}
        outs["panoproj (auto)"] = work / "p.mkv"
        subprocess.run([str(CLI), "convert", str(src), str(outs["panoproj (auto)"]), "--to", "equirect", "--size",
                        f"{OW}x{OH}", "--yaw", str(YAW), "--pitch", str(PITCH), "--codec", "ffv1", "-q"], check=True)
        outs["panoproj (off)"] = work / "p_off.mkv"
        subprocess.run([str(CLI), "convert", str(src), str(outs["panoproj (off)"]), "--to", "equirect", "--size",
                        f"{OW}x{OH}", "--yaw", str(YAW), "--pitch", str(PITCH), "--codec", "ffv1", "--antialias", "off",
                        "-q"], check=True)
        for interp in ("line", "cubic"):
            # (v360's yaw and pitch turn as panoproj's: of the four signs, these match the truth.)
            outs[f"v360 {interp}"] = work / f"v_{interp}.mkv"
            subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", str(src), "-vf",
                            f"v360=e:e:yaw={YAW}:pitch={PITCH}:interp={interp}:w={OW}:h={OH}", "-c:v", "ffv1",
                            str(outs[f"v360 {interp}"])], check=True)
        print(f"{SW}x{SH} -> {OW}x{OH} equirect, yaw {YAW}, pitch {PITCH}, {FRAMES} frames, FFV1 both ways")
        for name, f in outs.items():
            got = planes(f, work)
            mse_y = np.mean([np.mean((g[0] - t[0]) ** 2) for g, t in zip(got, truths)])
            rms_c = np.sqrt(np.mean([np.mean((g[c] - t[c]) ** 2) for g, t in zip(got, truths) for c in (1, 2)]))
            print(f"{name:16s} luma PSNR {10 * np.log10(255 ** 2 / mse_y):5.2f} dB   chroma RMS error {rms_c:.3f} LSB")


if __name__ == "__main__":
    main()
