"""PNG figures of the verification scripts (matplotlib from Debian's python3-matplotlib; without
it no figure is drawn and the checks run as before)."""


def save_plot(directory, name, draw, figsize=(6, 4.5)):
    """directory/name.png of one axes that draw(ax) fills (labels, title), with a grid and legend."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    directory.mkdir(exist_ok=True)
    fig, ax = plt.subplots(figsize=figsize)
    draw(ax)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(directory / f"{name}.png", dpi=110)
    plt.close(fig)
