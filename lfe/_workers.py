"""What every task of ``compare`` and ``study`` loads first, in whichever process runs it."""

import baselines


def load_libraries():
    """Import torch in this process (nothing to do once it is loaded).

    With ``n_jobs > 1`` the tasks run in loky's worker processes. loky measures a worker's
    memory after its first task and stops a worker that has grown by 300 MB since, warning "A
    worker stopped while some jobs were given to the executor"; torch's import alone adds about
    240 MB, so a worker whose first task was a BSI fit or a simulation was stopped and replaced
    when it met its first network. Loaded at the start of every task, torch is inside that
    first measure, and a stopped worker would mean a real leak.
    """
    baselines.require_torch()
