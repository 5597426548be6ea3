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


# ----------------------------------------------------------------------------- the notice
def _fresh_package_kernel():
    # A function of the package as far as the notice can tell (its module is bsi_sklearn's).
    def kernel(x):
        return x * 2

    kernel.__module__ = "bsi_sklearn._a_test_kernel"
    return njit(kernel)


def _notice(**kwargs):
    import io

    from bsi_sklearn._compile_progress import _Notice

    stream = io.StringIO()
    return _Notice(stream=stream, **kwargs), stream


def _compile_under(listener, kernel):
    from numba.core import event

    with event.install_listener("numba:compile", listener):
        kernel(1)


def test_one_line_when_the_package_compiles_longer_than_the_delay():
    from bsi_sklearn._compile_progress import NOTICE

    notice, stream = _notice(delay=0.0)
    _compile_under(notice, _fresh_package_kernel())
    _compile_under(notice, _fresh_package_kernel())  # the same burst: no second line
    assert stream.getvalue() == NOTICE + "\n"
    assert "python -m bsi_sklearn.compile" in NOTICE


def test_a_new_burst_after_a_quiet_gap_says_it_again():
    notice, stream = _notice(delay=0.0, quiet_gap=0.0)
    _compile_under(notice, _fresh_package_kernel())
    _compile_under(notice, _fresh_package_kernel())
    assert stream.getvalue().count("\n") == 2


def test_no_line_for_a_short_compilation_another_package_or_under_a_bar():
    from bsi_sklearn._compile_progress import quiet_notice

    notice, stream = _notice(delay=60.0)
    _compile_under(notice, _fresh_package_kernel())  # far shorter than a minute
    notice, stream_other = _notice(delay=0.0)
    _compile_under(notice, _fresh_kernel())  # not the package's
    with quiet_notice():
        notice, stream_bar = _notice(delay=0.0)
        notice.bars = 1  # as compile_progress(verbose > 0) and the compile step set it
        _compile_under(notice, _fresh_package_kernel())
    assert stream.getvalue() == stream_other.getvalue() == stream_bar.getvalue() == ""


def test_the_timer_prints_while_a_compilation_is_still_running():
    import time

    from numba.core import event

    notice, stream = _notice(delay=0.05)
    ev = event.Event(kind="numba:compile", status=event.EventStatus.START,
                     data={"dispatcher": _fresh_package_kernel()})
    notice.on_start(ev)  # a long compilation starts, and no event follows for a while
    time.sleep(0.5)
    assert stream.getvalue().count("\n") == 1
    notice.on_end(ev)
