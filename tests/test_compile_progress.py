"""The bar shown while numba compiles on first use (bsi_sklearn._compile_progress)."""

from numba import njit

from bsi_sklearn._compile_progress import compile_progress


def _fresh_kernel():
    # A new function object each call: numba compiles it on its first call.
    @njit
    def kernel(x):
        return x + 1

    return kernel


def test_a_bar_counts_the_kernels_compiled_inside_the_block(capsys):
    with compile_progress(1):
        assert _fresh_kernel()(1) == 2
    err = capsys.readouterr().err
    assert "compiling numba kernels" in err
    assert "1kernel" in err.replace(" ", "")


def test_nothing_is_shown_without_compilation_or_with_verbose_0(capsys):
    kernel = _fresh_kernel()
    kernel(1)  # compiled now
    with compile_progress(1):
        kernel(2)
    with compile_progress(0):
        _fresh_kernel()(3)
    assert "compiling" not in capsys.readouterr().err
