"""Reads the VTK XML files mgelastic writes (.vti, .vtp, .vtu) in either encoding.

Written from the VTK XML file-format description, independently of the C++ writer: an ASCII
DataArray holds its values as text; an appended one points (attribute `offset`) into the raw bytes
after the '_' of <AppendedData encoding="raw">. With compressor="vtkZLibDataCompressor" each array
there is a header of header_type integers [blocks, block size, size of the last block (0 = full),
compressed size of each block] followed by the zlib-compressed blocks; without a compressor, one
integer (the byte count) followed by the bytes.

    root, arrays = vtk_xml.read("out/grid_0000.vti")
    arrays["displacement"]  # list of numbers; unnamed arrays under their parent's tag ("Points")

`python3 vtk_xml.py FILE...` prints each array's name, type and length.
"""
import struct
import sys
import xml.etree.ElementTree as E
import zlib

TYPES = {"Int8": "b", "UInt8": "B", "Int16": "h", "UInt16": "H", "Int32": "i", "UInt32": "I",
         "Int64": "q", "UInt64": "Q", "Float32": "f", "Float64": "d"}


def _appended_bytes(raw, offset, header, compressed):
    size = struct.calcsize("<" + header)
    if not compressed:
        (count,) = struct.unpack_from("<" + header, raw, offset)
        return raw[offset + size:offset + size + count]
    blocks, block_size, last_size = struct.unpack_from("<" + header * 3, raw, offset)
    sizes = struct.unpack_from("<" + header * blocks, raw, offset + 3 * size)
    position = offset + (3 + blocks) * size
    data = []
    for b, compressed_size in enumerate(sizes):
        block = zlib.decompress(raw[position:position + compressed_size])
        expected = last_size if b == blocks - 1 and last_size else block_size
        assert len(block) == expected, (len(block), expected)
        data.append(block)
        position += compressed_size
    return b"".join(data)


def _values(array, raw, header, compressed):
    code = TYPES[array.get("type")]
    if array.get("format") == "ascii":
        convert = float if code in "fd" else int
        return [convert(x) for x in (array.text or "").split()]
    assert array.get("format") == "appended", array.get("format")
    data = _appended_bytes(raw, int(array.get("offset")), header, compressed)
    return list(struct.unpack("<%d%s" % (len(data) // struct.calcsize(code), code), data))


def read(path):
    """The XML root element and {array name: values} of a .vti/.vtp/.vtu file."""
    data = open(path, "rb").read()
    start = data.find(b"<AppendedData")
    if start < 0:
        root, raw = E.fromstring(data), b""
    else:
        # The raw bytes are not XML: parse the part before them, closed.
        root = E.fromstring(data[:start] + b"</VTKFile>")
        raw = data[data.index(b"_", start) + 1:]
    assert root.get("byte_order", "LittleEndian") == "LittleEndian"
    header = TYPES[root.get("header_type", "UInt32")]
    compressor = root.get("compressor")
    assert compressor in (None, "vtkZLibDataCompressor"), compressor
    arrays = {}
    for parent in root.iter():
        for array in parent.findall("DataArray"):
            arrays[array.get("Name") or parent.tag] = _values(array, raw, header, compressor)
    return root, arrays


if __name__ == "__main__":
    for name in sys.argv[1:]:
        root, arrays = read(name)
        for key, values in arrays.items():
            print(name, key, len(values))
