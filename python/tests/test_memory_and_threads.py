"""No copy of C-contiguous input; the GIL is released while converting; plans shared by threads."""
import sys
import threading

import numpy as np

import panoproj as pp
from conftest import smooth_equirect


def test_c_contiguous_input_is_read_in_place():
    a = smooth_equirect(256, 128)
    assert pp._core._pixels_address(a) == a.__array_interface__["data"][0]
    ro = np.frombuffer(a.tobytes(), np.uint8).reshape(a.shape)  # read-only memory is fine too
    assert not ro.flags.writeable
    assert pp._core._pixels_address(ro) == ro.__array_interface__["data"][0]
    # Other layouts are copied once, to C order, and give the same result.
    f = np.asfortranarray(a)
    assert pp._core._pixels_address(f) != f.__array_interface__["data"][0]
    strided = smooth_equirect(512, 128)[:, ::2]
    assert np.array_equal(pp.convert(f, "equirect", "pinhole", size=(64, 64)),
                          pp.convert(a, "equirect", "pinhole", size=(64, 64)))
    assert pp.convert(strided, "equirect", "pinhole", size=(64, 64)).shape == (64, 64, 3)


def test_output_is_handed_over_without_a_copy():
    out = pp.convert(smooth_equirect(256, 128), "equirect", "pinhole", size=(64, 48))
    assert out.flags.c_contiguous and out.flags.writeable and out.base is not None


def test_the_gil_is_released_during_a_conversion():
    # With a huge switch interval the interpreter never takes the GIL from a running thread:
    # the main thread can run while the worker is inside convert() only if convert() released
    # it. No timing is involved: if the GIL were held, the main thread would first run when
    # the worker had finished, and would see `done` already set.
    img = smooth_equirect(2048, 1024)
    entered, done = threading.Event(), threading.Event()
    steps = []

    def worker():
        entered.set()
        pp.convert(img, "equirect", "cubemap", size=(6 * 512, 512), threads=1, interp="lanczos3")
        done.set()

    old = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    try:
        t = threading.Thread(target=worker)
        t.start()
        entered.wait()
        while not done.is_set() and len(steps) < 1000:
            steps.append(1)
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert len(steps) == 1000, "the main thread only ran after the conversion: the GIL was held"


def test_one_plan_shared_by_two_threads_gives_the_single_thread_bytes():
    img = smooth_equirect(1024, 512)
    plan = pp.Plan("equirect", "aitoff", (1024, 512), size=(512, 256), threads=1)  # a kept map
    expected = pp.Plan("equirect", "aitoff", (1024, 512), size=(512, 256), threads=1)(img)
    results = [None] * 4

    def run(i):
        results[i] = plan(img)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(r, expected) for r in results)


def test_plan_writes_into_a_given_array():
    img = smooth_equirect(512, 256)
    plan = pp.Plan("equirect", "fisheye", (512, 256), size=(128, 128))
    out = np.zeros((128, 128, 3), np.uint8)
    assert plan.run(img, out=out) is out
    assert np.array_equal(out, plan(img))
