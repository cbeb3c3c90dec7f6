"""plots."""

#: Resolution of every PNG the plots write.
DPI = 150


def write_figure(fig, path, tight=True):
    """Write ``fig`` as the PNG ``path``, and as vector PDF beside it, and
    close it (``tight``: lay it out tightly first); returns ``path``."""
    from pathlib import Path

    import matplotlib.pyplot as plt

    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    fig.savefig(Path(path).with_suffix(".pdf"), bbox_inches="tight")
    plt.close(fig)
    return path
