"""matplotlib figures of postprocess.py (one function per kind of figure). Without matplotlib in this
Python, every function says which file it skipped and returns None."""
import os

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    MPL_ERROR = None
except Exception as e:  # pragma: no cover - depends on the installation
    plt = None
    MPL_ERROR = str(e)

STYLES = ["-", "--", ":", "-."]


def available(path):
    if plt is None:
        print("skipped %s: matplotlib does not import in this Python (%s); install python3-matplotlib"
              % (path, MPL_ERROR))
        return False
    return True


def _save(fig, ax, path, title, xlabel, ylabel, legend=True):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    if legend and ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def lines(path, runs, xlabel, ylabel, title, markers=None):
    """``runs``: [(run label, [(series label, x, y), ...])]; one line style per run, one colour per series.
    ``markers``: [(label, x, y)] drawn as points (measurements)."""
    if not available(path):
        return None
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (run_label, series) in enumerate(runs):
        for j, (label, x, y) in enumerate(series):
            name = label if len(runs) == 1 else "%s (%s)" % (label, run_label)
            ax.plot(x, y, STYLES[k % len(STYLES)], color=colours[j % len(colours)], lw=1.4, label=name,
                    marker="o" if len(x) < 30 else None, ms=3)
    for j, (label, x, y) in enumerate(markers or []):
        ax.plot(x, y, "ks^Dv"[j % 5] if j else "ko", ms=4, mfc="none", label=label)
    return _save(fig, ax, path, title, xlabel, ylabel)
