"""hydrocli.blas.single_threaded: every loaded OpenBLAS runs on one thread inside the block,
the previous counts come back after it (also after an exception), and nesting is safe."""
import numpy as np
import pytest
import scipy.linalg  # noqa: F401  (loads SciPy's own OpenBLAS)

from hydrocli.blas import single_threaded, thread_counts


def test_single_threaded_sets_and_restores():
    before = thread_counts()
    if not before:
        pytest.skip("no OpenBLAS found in this process")
    with single_threaded():
        assert thread_counts() == [1] * len(before)
        with single_threaded():
            assert thread_counts() == [1] * len(before)
        assert thread_counts() == [1] * len(before)      # the inner block does not restore early
    assert thread_counts() == before
    with pytest.raises(RuntimeError):
        with single_threaded():
            raise RuntimeError("boom")
    assert thread_counts() == before


def test_results_match_multithreaded_to_rounding():
    rng = np.random.default_rng(0)
    J = rng.standard_normal((20000, 15))
    s_ref = np.linalg.svd(J, compute_uv=False)
    with single_threaded():
        s_one = scipy.linalg.svd(J, compute_uv=False)
    np.testing.assert_allclose(s_one, s_ref, rtol=1e-12)


def test_the_benchmark_times_its_runs_with_blas_on_one_thread():
    """hydro bench's timer measures CPU time of the process, which would also count OpenBLAS's
    idle threads spin-waiting; it must run what it times with BLAS on one thread."""
    from hydrocli.bench import _median_time

    before = thread_counts()
    if not before:
        pytest.skip("no OpenBLAS found in this process")
    _, inside = _median_time(thread_counts, 3)
    assert inside == [1] * len(before)
    assert thread_counts() == before
