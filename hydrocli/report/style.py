"""One look for every report page: A4 (landscape for the model report, portrait for the
diagnosis), readable fonts, fixed colours, table helper. Figures are plain
``matplotlib.figure.Figure`` objects saved into a PdfPages document (``report.document``):
no pyplot state and no backend switch at import."""
from __future__ import annotations

from matplotlib.figure import Figure

PAGE = (11.69, 8.27)                # A4 landscape, inches
PORTRAIT = (8.27, 11.69)            # A4 portrait, inches
MEASURED = "#1f1f1f"
SIMULATED = "#d62728"
RESIDUAL = "#1f77b4"
WINDOW = "#ffbf00"
ROW_IN = 0.24                       # table row height, inches
RC = {
    "font.size": 9, "axes.titlesize": 10, "axes.labelsize": 9, "legend.fontsize": 8,
    "xtick.labelsize": 8, "ytick.labelsize": 8, "axes.grid": True, "grid.alpha": 0.3,
    "lines.linewidth": 0.9, "axes.spines.top": False, "axes.spines.right": False,
    "figure.dpi": 100,
}


def figure(size: tuple[float, float] = PAGE) -> Figure:
    """A new blank page (A4 landscape by default; ``PORTRAIT`` for the diagnosis)."""
    return Figure(figsize=size)


def page(title: str, subtitle: str = ""):
    """A new A4 landscape figure with a page title (and an optional grey subtitle)."""
    fig = figure(PAGE)
    fig.text(0.04, 0.965, title, fontsize=14, weight="bold", va="top")
    if subtitle:
        fig.text(0.04, 0.93, subtitle, fontsize=9, color="0.35", va="top")
    return fig


def rows_fitting(height: float) -> int:
    """Table rows (besides the header) that fit in ``height`` (figure fraction)."""
    return max(0, int(height * PAGE[1] / ROW_IN) - 1)


def footer(fig, text: str) -> None:
    fig.text(0.5, 0.015, text, fontsize=7, color="0.5", ha="center")


def table(ax, header: list[str], rows: list[list[str]], col_widths: list[float] | None = None,
          highlight: dict[int, str] | None = None, font: float = 8.5, left: int = 1) -> float:
    """A plain table at the top of ``ax`` (axis hidden); ``highlight`` maps row index → colour.
    Returns the bottom of the table in figure coordinates."""
    ax.axis("off")
    pos = ax.get_position()
    if not rows:
        ax.text(0.0, 0.9, "(nothing to show)", color="0.4", transform=ax.transAxes)
        return pos.y1 - 0.05
    height_in = ax.get_position().height * ax.figure.get_figheight()
    h = min(1.0, (len(rows) + 1) * ROW_IN / height_in)
    t = ax.table(cellText=rows, colLabels=header, colWidths=col_widths, loc="upper left", cellLoc="right",
                 colLoc="center", bbox=[0, 1 - h, 1, h])
    t.auto_set_font_size(False)
    t.set_fontsize(font)
    for (r, c), cell in t.get_celld().items():
        cell.set_edgecolor("0.8")
        if c < left:
            cell.set_text_props(ha="left")
            cell.PAD = 0.03
        if r == 0:
            cell.set_facecolor("0.92")
            cell.set_text_props(weight="bold", ha="center")
        elif highlight and (r - 1) in highlight:
            cell.set_facecolor(highlight[r - 1])
    return pos.y1 - h * pos.height


class Pages:
    """Numbers, footers, saves and closes the pages of one PdfPages document."""

    def __init__(self, pdf, footer_text: str = ""):
        self.pdf, self.footer_text, self.count = pdf, footer_text, 0

    def add(self, fig) -> None:
        self.count += 1
        footer(fig, f"{self.footer_text}   —   page {self.count}" if self.footer_text else f"page {self.count}")
        self.pdf.savefig(fig)
