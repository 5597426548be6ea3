"""torch is the optional extra ``[baselines]``: the classifier, simulation and extraction run
without it, and a network asked for without it fails with a message naming the extra."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# A meta-path finder that makes ``import torch`` (and any ``torch.*``) fail as if torch were
# not installed, installed before anything else is imported.
BLOCK_TORCH = textwrap.dedent("""
    import sys

    class BlockTorch:
        def find_spec(self, name, path=None, target=None):
            if name == "torch" or name.startswith("torch."):
                raise ModuleNotFoundError(f"No module named {name!r}", name=name)
            return None

    sys.meta_path.insert(0, BlockTorch())
""")

SCRIPT = BLOCK_TORCH + textwrap.dedent("""
    import numpy as np

    try:
        import torch  # noqa: F401
    except ModuleNotFoundError:
        pass
    else:
        raise SystemExit("the finder did not block torch")

    # the classifier
    import bsi_sklearn
    from bsi_sklearn import BSIClassifier

    good = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
            np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    bad = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], random_state=0)
    clf.fit(good + bad, [1, 1, 0])
    print("MAP", clf.map_specification_.to_ltl())
    print("PROBA", clf.predict_proba(bad)[0, 1] < 0.5)

    # the LFE domain: simulation, the commander's labels, extraction; the CLI wiring
    import lfe
    import lfe.cli
    import lfe.compare
    from lfe import LFEPropositionExtractor, make_lfe_dataset

    ds = make_lfe_dataset(n_scenarios=2, random_state=0)
    X = LFEPropositionExtractor().fit_transform(ds.scenarios)
    print("LFE", len(X), X[0].shape[1] > 0, sorted(ds.labels.columns))
    lfe.cli.build_parser()

    # the baselines' table is torch-free; the networks are not
    import baselines

    print("TABLE", sorted(baselines.PAPER_BASELINES))
    for request in (lambda: baselines.make_paper_baseline("LSTM"),
                    lambda: baselines.LSTMSequenceClassifier(),
                    lambda: __import__("baselines.lstm"),
                    baselines.require_torch,
                    lambda: lfe.compare.compare(ds, n_splits=2, quick=True, verbose=0)):
        try:
            request()
        except ModuleNotFoundError as exc:
            print("ERROR", exc.name, "|", exc)
        else:
            raise SystemExit("a network was built without torch")
    print("TORCH LOADED", "torch" in sys.modules)
""")


def test_classifier_and_lfe_work_without_torch():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("MPLBACKEND", "Agg")
    proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          cwd=ROOT, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    out = proc.stdout.splitlines()
    assert "MAP G(0) & F(1) & F(2) & (!2 U 1)" in out
    assert "PROBA True" in out
    assert "LFE 2 True ['MO1', 'MO2', 'MO3']" in out
    assert "TABLE ['Bi-LSTM', 'Bi-LSTM Coupled', 'LSTM', 'LSTM Coupled']" in out
    errors = [line for line in out if line.startswith("ERROR")]
    assert len(errors) == 5
    for line in errors:
        assert line.startswith("ERROR torch |")
        assert 'pip install "bsi-sklearn[baselines]"' in line
    assert "TORCH LOADED False" in out
