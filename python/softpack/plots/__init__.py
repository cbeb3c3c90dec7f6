"""plots."""

#: Resolution of every PNG the plots write.
DPI = 150


def write_figure(fig, path, tight=True):
    """Write ``fig`` as the PNG ``path`` and close it (``tight``: lay it out
    tightly first); returns ``path``."""
    import matplotlib.pyplot as plt

    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path
