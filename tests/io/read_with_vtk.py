"""Reads VTK XML files with VTK's own readers (python3-vtk9) and dumps their arrays.

    read_with_vtk.py OUT_DIR FILE...

For each FILE (.vti, .vtp, .vtu) and each of its point and cell arrays, writes
OUT_DIR/<file name>.<array name>.f64: the values, tuples contiguous, as little-endian Float64.
Points and cells of .vtp/.vtu go out as 'Points', 'connectivity', 'offsets' and, for .vtu,
'types'. Exit status 2 when a reader reports an error (VTK's readers only warn).
"""
import os
import sys

import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy


class ErrorObserver:
    def __init__(self):
        self.errors = []

    def __call__(self, caller, event):
        self.errors.append(event)


def dump(out_dir, path):
    readers = {".vti": vtk.vtkXMLImageDataReader, ".vtp": vtk.vtkXMLPolyDataReader,
               ".vtu": vtk.vtkXMLUnstructuredGridReader}
    reader = readers[os.path.splitext(path)[1]]()
    observer = ErrorObserver()
    reader.AddObserver("ErrorEvent", observer)
    reader.GetExecutive().AddObserver("ErrorEvent", observer)
    reader.SetFileName(path)
    reader.Update()
    if observer.errors:
        sys.exit(2)
    data = reader.GetOutput()
    arrays = {}
    for attributes in (data.GetPointData(), data.GetCellData()):
        for i in range(attributes.GetNumberOfArrays()):
            arrays[attributes.GetArrayName(i)] = attributes.GetArray(i)
    if isinstance(data, vtk.vtkPolyData):
        arrays["Points"] = data.GetPoints().GetData()
        arrays["connectivity"] = data.GetPolys().GetConnectivityArray()
        arrays["offsets"] = data.GetPolys().GetOffsetsArray()
    elif isinstance(data, vtk.vtkUnstructuredGrid):
        arrays["Points"] = data.GetPoints().GetData()
        arrays["connectivity"] = data.GetCells().GetConnectivityArray()
        arrays["offsets"] = data.GetCells().GetOffsetsArray()
        arrays["types"] = data.GetCellTypesArray()
    name = os.path.basename(path)
    for array_name, array in arrays.items():
        values = vtk_to_numpy(array).astype("<f8").ravel()
        values.tofile(os.path.join(out_dir, name + "." + array_name + ".f64"))


for file in sys.argv[2:]:
    dump(sys.argv[1], file)
