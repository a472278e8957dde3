"""The report's figures, as plotly Figures (markup.figure puts them into a page).

pareto: error against median frame time, log-log, the budgets and the bands drawn;
surface: a Scatter3d of surface vertices coloured by a value; lines and bars: the
generic charts the other pages use. Arrays are numpy: points #V x 3, values #V.
"""
import math

import numpy as np
import plotly.colors
import plotly.graph_objects as go

import leaderboard

TEMPLATE = "plotly_white"
PALETTE = plotly.colors.qualitative.Dark24
BAND_COLOURS = (("rgba(255,160,0,0.16)", "rgb(230,140,0)"), ("rgba(60,120,220,0.14)", "rgb(60,120,220)"))  # fill, edge
ERROR_FLOOR = 1e-6  # an error of 0 (a case equal to its reference) drawn here on the log axis
TIME_FLOOR_MS = 1e-4


def colours(names):
    """{name: colour}, the same name the same colour on every page (sorted names, one palette)."""
    return {n: PALETTE[i % len(PALETTE)] for i, n in enumerate(sorted(set(names)))}


def log_range(values, pad=2.0):
    """[log10 low, log10 high] of the positive values, padded by a factor each way."""
    v = [x for x in values if x > 0 and math.isfinite(x)]
    return [math.log10(min(v) / pad), math.log10(max(v) * pad)]


def pareto(points, bands, budgets, title, y_title, model_colours):
    """points: [{case, model, time_ms, error, settled, hover}] (the Pareto front's named, every one
    on hover); bands: [(low, high, text)] shaded across the plot (a low of 0: from the axis'
    bottom); budgets: ms, drawn as vertical lines."""
    fig = go.Figure()
    shown = [dict(p, time_ms=max(p["time_ms"], TIME_FLOOR_MS), error=max(p["error"], ERROR_FLOOR)) for p in points]
    xr = log_range([p["time_ms"] for p in shown] + list(budgets))
    yr = log_range([p["error"] for p in shown] + [v for b in bands for v in b[:2]])
    for (low, high, text), (fill, edge) in zip(bands, BAND_COLOURS):
        x0, x1 = 10 ** xr[0], 10 ** xr[1]
        y0 = max(low, 10 ** yr[0]) if low > 0 else 10 ** yr[0]
        fig.add_trace(go.Scatter(x=[x0, x1, x1, x0, x0], y=[y0, y0, high, high, y0], fill="toself", mode="lines",
                                 line={"width": 1, "color": edge, "dash": "dash"}, fillcolor=fill, name=text,
                                 hoverinfo="name"))
    front = pareto_front(shown)
    on_front = {p[2] for p in front}
    for model in sorted({p["model"] for p in shown}):
        mine = [p for p in shown if p["model"] == model]
        fig.add_trace(go.Scatter(
            x=[p["time_ms"] for p in mine], y=[p["error"] for p in mine], mode="markers+text", name=model,
            text=[p["case"] if p["case"] in on_front else "" for p in mine], textposition="top center",
            textfont={"size": 10},
            hovertext=[p["hover"] for p in mine], hoverinfo="text",
            marker={"size": 9, "color": model_colours[model],
                    "symbol": ["circle" if p["settled"] else "x" for p in mine]}))
    if front:
        fig.add_trace(go.Scatter(x=[p[0] for p in front], y=[p[1] for p in front], mode="lines", name="Pareto front",
                                 line={"shape": "hv", "color": "rgba(0,0,0,0.45)", "width": 1.5}, hoverinfo="skip"))
    for b in budgets:  # a shape takes data values on a log axis, an annotation their log10
        fig.add_shape(type="line", xref="x", yref="paper", x0=b, x1=b, y0=0, y1=1,
                      line={"color": "grey", "dash": "dot", "width": 1})
        fig.add_annotation(x=math.log10(b), y=1, xref="x", yref="paper", yanchor="bottom", text=f"{b:g} ms",
                           showarrow=False, font={"size": 11, "color": "grey"})
    fig.update_layout(template=TEMPLATE, title=title, hovermode="closest", legend={"font": {"size": 11}},
                      xaxis={"type": "log", "range": xr, "title": "median time per frame (ms)"},
                      yaxis={"type": "log", "range": yr, "title": y_title}, margin={"t": 60})
    return fig


def pareto_front(points):
    """(time, error) of the points no other point beats in both, sorted by time (leaderboard.pareto_front)."""
    return leaderboard.pareto_front([(p["time_ms"], p["error"], p["case"]) for p in points])


def surface(xyz, views, title):
    """A Scatter3d of #V vertices (xyz #V x 3, mm), axes to scale, coloured by one of
    views [(label, values #V, colour bar title)]: the first shown, a menu for the others
    (one WebGL scene whatever their number)."""
    fig = go.Figure()
    for i, (label, values, colour_title) in enumerate(views):
        marker = {"size": 3, "color": values, "colorscale": "Viridis", "colorbar": {"title": colour_title},
                  "cmin": float(np.min(values)), "cmax": float(np.max(values))}
        fig.add_trace(go.Scatter3d(x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2], mode="markers", marker=marker, name=label,
                                   visible=i == 0, hovertemplate="%{marker.color:.3g}<extra></extra>"))
    if len(views) > 1:
        buttons = [{"label": label, "method": "update", "args": [{"visible": [j == i for j in range(len(views))]}]}
                   for i, (label, _, _) in enumerate(views)]
        fig.update_layout(updatemenus=[{"buttons": buttons, "x": 0, "xanchor": "left", "y": 1, "yanchor": "top"}])
    fig.update_layout(template=TEMPLATE, title={"text": title, "font": {"size": 14}}, showlegend=False,
                      margin={"l": 0, "r": 0, "b": 0, "t": 40},
                      scene={"aspectmode": "data", "xaxis_title": "x (mm)", "yaxis_title": "y (mm)",
                             "zaxis_title": "z (mm)"})
    return fig


def lines(series, title, x_title, y_title, log_x=False, log_y=False, hlines=(), mode="lines+markers"):
    """series: [(name, x #N, y #N, extra trace properties {})]; hlines: [(y, text)] drawn across."""
    fig = go.Figure()
    for name, x, y, extra in series:
        fig.add_trace(go.Scatter(x=list(x), y=list(y), mode=mode, name=name, **extra))
    for y, text in hlines:
        fig.add_shape(type="line", xref="paper", x0=0, x1=1, yref="y", y0=y, y1=y,
                      line={"color": "grey", "dash": "dot", "width": 1})
        fig.add_annotation(xref="paper", x=0, yref="y", y=math.log10(y) if log_y else y, text=text,
                           showarrow=False, xanchor="left", yanchor="bottom", font={"size": 11, "color": "grey"})
    fig.update_layout(template=TEMPLATE, title={"text": title, "font": {"size": 15}}, hovermode="closest",
                      xaxis={"type": "log" if log_x else "linear", "title": x_title},
                      yaxis={"type": "log" if log_y else "linear", "title": y_title})
    return fig


def bars(categories, series, title, y_title, log_y=False):
    """Grouped bars: categories #C, series [(name, values #C)] (NaN: no bar)."""
    fig = go.Figure([go.Bar(x=list(categories), y=[None if not math.isfinite(v) else v for v in values], name=name)
                     for name, values in series])
    fig.update_layout(template=TEMPLATE, title={"text": title, "font": {"size": 15}}, barmode="group",
                      yaxis={"type": "log" if log_y else "linear", "title": y_title})
    return fig
