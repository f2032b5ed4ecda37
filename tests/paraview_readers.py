"""paraview_readers.py RESULT OUT.json [PNG] — run by pvbatch for check_paraview.py.

Opens RESULT/frames.xdmf with Xdmf3ReaderT, Xdmf3ReaderS and XDMFReader, and
RESULT/frames_particles.xdmf with Xdmf3ReaderS, at the first and the last time; writes
for each reader and time the blocks (name, points, cells, point and cell array names)
as JSON. With PNG, renders the last frame of frames_particles.xdmf as Point Gaussian
scaled by radius (the way docs/output.md#paraview says) on a white background."""
import json
import sys

from paraview import servermanager as sm
from paraview.simple import (ColorBy, CreateRenderView, Render, SaveScreenshot, Show,
                             XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT)


def leaves(obj, name=None):
    """(name, dataset) of every leaf of a composite dataset."""
    if obj is None:
        return [(name, None)]
    if obj.IsA("vtkMultiPieceDataSet"):
        out = []
        for i in range(obj.GetNumberOfPieces()):
            out += leaves(obj.GetPiece(i), name)
        return out
    if obj.IsA("vtkMultiBlockDataSet"):
        out = []
        for i in range(obj.GetNumberOfBlocks()):
            md = obj.GetMetaData(i) if obj.HasMetaData(i) else None
            nm = md.Get(obj.NAME()) if md is not None and md.Has(obj.NAME()) else None
            out += leaves(obj.GetBlock(i), nm)
        return out
    return [(name, obj)]


def describe(ds):
    if ds is None:
        return None
    pd, cd = ds.GetPointData(), ds.GetCellData()
    return {"points": ds.GetNumberOfPoints(), "cells": ds.GetNumberOfCells(),
            "point_arrays": [pd.GetArrayName(k) for k in range(pd.GetNumberOfArrays())],
            "cell_arrays": [cd.GetArrayName(k) for k in range(cd.GetNumberOfArrays())]}


def main():
    res, out = sys.argv[1], sys.argv[2]
    full, parts = res + "/frames.xdmf", res + "/frames_particles.xdmf"
    readers = {"Xdmf3ReaderT": lambda: Xdmf3ReaderT(FileName=full),
               "Xdmf3ReaderS": lambda: Xdmf3ReaderS(FileName=full),
               "XDMFReader": lambda: XDMFReader(FileNames=[full]),
               "Xdmf3ReaderS particles": lambda: Xdmf3ReaderS(FileName=parts)}
    report = {}
    for name, make in readers.items():
        r = make()
        times = list(r.TimestepValues)
        report[name] = {"times": times, "at": []}
        for t in (times[0], times[-1]):
            r.UpdatePipeline(t)
            report[name]["at"].append(
                {"time": t, "blocks": [[nm, describe(ds)] for nm, ds in
                                       leaves(sm.Fetch(r))]})
    if len(sys.argv) > 3:
        r = Xdmf3ReaderS(FileName=parts)
        t = r.TimestepValues[-1]
        r.UpdatePipeline(t)
        view = CreateRenderView()
        view.ViewSize = [300, 300]
        view.OrientationAxesVisibility = 0
        view.ViewTime = t
        d = Show(r, view)
        ColorBy(d, None)
        d.AmbientColor = d.DiffuseColor = [0.8, 0.1, 0.1]
        d.SetRepresentationType("Point Gaussian")
        d.ScaleByArray = 1
        d.SetScaleArray = ["POINTS", "radius"]
        d.UseScaleFunction = 0
        d.GaussianRadius = 1.0
        view.ResetCamera()
        Render(view)
        SaveScreenshot(sys.argv[3], view, ImageResolution=[300, 300],
                       OverrideColorPalette="WhiteBackground")
    with open(out, "w") as fh:
        json.dump(report, fh)


main()
