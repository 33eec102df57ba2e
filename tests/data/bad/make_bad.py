#!/usr/bin/env python3
"""Writes the bad-input catalogue (run from this folder): one malformed file
per class and reader, and catalogue.csv naming, for each, the subcommand
that reads it ("force" or "scan") and a fragment the error must contain."""
import io, math, struct, zipfile

def entry(name, deflate=False):
    """A ZIP entry with a fixed date, so that the files are reproducible."""
    i = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
    i.compress_type = zipfile.ZIP_DEFLATED if deflate else zipfile.ZIP_STORED
    return i

rows = []
def put(name, data, kind, expected):
    open(name, 'wb').write(data if isinstance(data, bytes) else data.encode())
    rows.append((name, kind, expected))

good = ['time_s,x_mm,Q_N,P_N'] + [f'{i*0.01:.2f},{2.85*__import__("math").sin(6.2832*i*0.01):.4f},1.0,30.0' for i in range(400)]
def csv(lines): return '\n'.join(lines) + '\n'

# ---- force files
put('empty.csv', '', 'force', 'the file is empty')
put('no_columns.csv', csv(['alpha,beta,gamma'] + [f'{i},{i},{i}' for i in range(20)]), 'force', 'no column for position x')
put('non_numeric.csv', csv(good[:50] + ['0.49,1.0,abc,30'] + good[51:]), 'force', "found 'abc', expected a number")
put('ragged.csv', csv(good[:50] + ['0.49,1.0'] + good[51:]), 'force', 'ragged row: found 2 fields, expected 4')
put('time_backwards.csv', csv(good[:50] + [good[20]] + good[51:]), 'force', 'is not after the previous')
put('time_repeats.csv', csv(good[:50] + [good[49]] + good[50:]), 'force', 'is not after the previous')
put('nan_run.csv', csv(good[:50] + [f'{0.5+i*0.0001:.4f},,,' for i in range(60)]), 'force', 'consecutive missing values')
put('one_cycle.csv', csv(good[:130]), 'force', 'complete cycle(s)')
put('binary.csv', bytes(range(256)) * 16, 'force', 'no numeric data found')
put('unit_unknown.csv', csv(['time (s),x (furlong),Fx (N),Fz (N)'] + [l for l in good[1:]]), 'force', "has unit 'furlong'; expected a length unit")
put('no_time_no_rate.csv', csv(['x_mm;Q_N;P_N'] + [';'.join(l.split(',')[1:]) for l in good[1:]]), 'force', 'no time column and no sampling rate')
put('flat_x.csv', csv(['time_s,x_mm,Q_N,P_N'] + [f'{i*0.01:.2f},1.0,1.0,30.0' for i in range(400)]), 'force', 'a stroke of 0 mm (robust peak to peak of x)')
put('text_in_data.csv', csv(good[:60] + ['pause,pause,pause,pause'] + good[61:]), 'force', "found text 'pause' where a data row was expected")

# ---- GSF
def gsf(fields, data=b''):
    h = ('Gwyddion Simple Field 1.0\n' + fields).encode()
    return h + b'\0' * (4 - len(h) % 4) + data
put('bad_magic.gsf', b'Gwyddion Simple Feld 1.0\nXRes = 1\n\0\0\0', 'scan', 'which is not the magic of a .gsf file')
put('truncated.gsf', gsf('XRes = 4\nYRes = 4\n', b'\0' * 30), 'scan', 'data truncated: 30 bytes present, expected 64')
put('absurd.gsf', gsf('XRes = 70000\nYRes = 70000\n'), 'scan', 'exceeds 268435456 pixels')
put('no_nul.gsf', 'Gwyddion Simple Field 1.0\nXRes = 2\nYRes = 2\n', 'scan', 'no NUL byte ends the GSF header')
put('missing_yres.gsf', gsf('XRes = 2\n', b'\0' * 16), 'scan', 'header has no YRes')
put('trailing_text.gsf', gsf('XRes = 8abc\nYRes = 2\n', b'\0' * 64), 'scan', "XRes = '8abc'; expected a positive pixel count")

# ---- VK4 / VK6
def vk4(w, h, bits, size, pixels, magic=b'VK4_', cond_pm=(7413000, 7413000, 100)):
    b = bytearray(magic + b'\0' * 8 + b'\0' * 72)
    cond = len(b); b += b'\0' * 200
    struct.pack_into('<3I', b, cond + 168, *cond_pm)
    img = len(b); hdr = bytearray(796); struct.pack_into('<5I', hdr, 0, w, h, bits, 0, size)
    b += hdr + b'\1' * pixels
    struct.pack_into('<I', b, 12, cond); struct.pack_into('<I', b, 36, img)
    return bytes(b)
put('bad_magic.vk4', vk4(2, 2, 32, 16, 16, magic=b'VK9_'), 'scan', "which is not the magic of a .vk4 file")
put('truncated.vk4', vk4(4, 4, 32, 64, 10), 'scan', 'truncated: the height pixels needs 64 bytes')
put('size_mismatch.vk4', vk4(4, 4, 32, 60, 64), 'scan', 'byte size 60 disagrees with 4 x 4 x 32 bits = 64')
put('absurd.vk4', vk4(100000, 100000, 32, 0, 0), 'scan', 'height image 100000 x 100000; expected 1 to 268435456 pixels')
put('zero_pitch.vk4', vk4(2, 2, 32, 16, 16, cond_pm=(0, 0, 100)), 'scan', 'expected positive values')
put('truncated.vk6', b'VK6\x10\x00\x00\x00BM', 'scan', 'truncated: the ZIP archive after the thumbnail')
buf = io.BytesIO()
with zipfile.ZipFile(buf, 'w') as z: z.writestr(entry('Other'), b'x')
put('no_vk4file.vk6', b'VK6' + struct.pack('<I', 2) + b'BM' + buf.getvalue(), 'scan', "the archive has no member 'Vk4File'")

# ---- ZON / ZAG
def grid(w, h, elem, stride, n):
    return struct.pack('<4i', w, h, elem, stride) + b'\0' * n
CAL = '<C><XYCalibration><MeterPerPixel>7e-6</MeterPerPixel></XYCalibration><ZCalibration><MeterPerUnit>1e-8</MeterPerUnit></ZCalibration></C>'
def kpk(members, magic=b'KPK0'):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, 'w') as z:
        for k, v in members.items(): z.writestr(entry(k), v)
    return magic + struct.pack('<I', 2) + b'BM' + buf.getvalue()
HG, CA = '4cdb0c75-5706-48cc-a9a1-adf395d609ae', '686613b8-27b5-4a29-8ffc-438c2780873e'
put('bad_magic.zon', b'KPX0' + b'\0' * 40, 'scan', 'which is not the magic of a .zon file')
put('not_zip.zon', b'KPK0' + struct.pack('<I', 0) + b'garbage here', 'scan', 'byte 8: no ZIP local-file header')
put('broken_zip.zon', b'KPK0' + struct.pack('<I', 0) + b'PK\x03\x04' + b'garbage here', 'scan', 'not a readable ZIP archive')
put('no_calibration.zon', kpk({HG: grid(2, 2, 4, 8, 16)}), 'scan', '(calibration XML) is missing')
put('no_heights.zon', kpk({CA: CAL}), 'scan', '(heights) is missing')
put('absurd.zon', kpk({HG: grid(100000, 100000, 4, 400000, 0), CA: CAL}), 'scan', '100000 x 100000 pixels; expected 1 to 268435456')
put('short_stride.zon', kpk({HG: grid(4, 2, 4, 8, 32), CA: CAL}), 'scan', 'row stride 8; expected 4 and at least 16')
put('truncated_rows.zon', kpk({HG: grid(4, 4, 4, 16, 20), CA: CAL}), 'scan', 'truncated: the pixel rows')
put('bad_calibration.zon', kpk({HG: grid(2, 2, 4, 8, 16), CA: '<C><XYCalibration><MeterPerPixel>-1</MeterPerPixel></XYCalibration></C>'}), 'scan', 'expected positive numbers')
put('kpk1_not_zstd.zon', kpk({HG: grid(2, 2, 4, 8, 16), CA: CAL}, magic=b'KPK1'), 'scan', '(zstd): not a zstd frame')
put('empty.zag', kpk({'f1724dc6-686c-4502-9227-2a594bc8ed33': '<Inventory/>'}), 'scan', 'no measurement payload')

# ---- x3p
def x3p(xml, members=None):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, 'w') as z:
        if xml is not None: z.writestr(entry('main.xml'), xml)
        for k, v in (members or {}).items():
            z.writestr(entry(k, deflate=len(v) > 1 << 20), v)
    return buf.getvalue()
def main_xml(sx, sy, dtype='D', link=True):
    rec3 = (f'<Record3><MatrixDimension><SizeX>{sx}</SizeX><SizeY>{sy}</SizeY><SizeZ>1</SizeZ></MatrixDimension>' +
            ('<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>' if link else '') + '</Record3>')
    return (f'<p:ISO5436_2 xmlns:p="x"><Record1><FeatureType>SUR</FeatureType><Axes>'
            f'<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment></CX>'
            f'<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment></CY>'
            f'<CZ><AxisType>A</AxisType><DataType>{dtype}</DataType></CZ></Axes></Record1>{rec3}</p:ISO5436_2>')
put('no_main.x3p', x3p(None, {'other.xml': '<a/>'}), 'scan', 'no main.xml in the archive')
put('bad_xml.x3p', x3p('<p:ISO5436_2><Record1>'), 'scan', 'XML error')
put('size_mismatch.x3p', x3p(main_xml(4, 4), {'bindata/data.bin': b'\0' * 100}), 'scan', "has 100 bytes; expected 128 for 4 x 4 values of type D")
put('absurd.x3p', x3p(main_xml(100000, 100000)), 'scan', 'MatrixDimension 100000 x 100000')
put('missing_data.x3p', x3p(main_xml(2, 2)), 'scan', "PointDataLink 'bindata/data.bin' is not in the archive")
put('bad_type.x3p', x3p(main_xml(2, 2, dtype='Q'), {'bindata/data.bin': b'\0' * 32}), 'scan', "CZ DataType 'Q'; expected I, L, F or D")

# ---- Keyence CSV and ASCII
put('keyence_no_pitch.csv', 'Horizontal,2\nVertical,2\nHeight\n1,2\n3,4\n', 'scan', "no 'XY Calibration' row")
put('keyence_ragged.csv', 'XY Calibration,7.4,um\nHeight\n1,2,3\n4,5\n', 'scan', 'line 4: 2 values; expected 3')
put('keyence_text_cell.csv', 'XY Calibration,7.4,um\nHeight\n1,2,3\n4,x,6\n', 'scan', "line 4, column 2: found 'x', expected a height")
put('ascii_no_pitch.txt', '1 2 3\n4 5 6\n7 8 9\n', 'scan', 'whose header states no pixel size')
put('ascii_line_profile.csv', 'Scan Data\nLateral um,Raw Micrometer,\n' + ''.join(f'{i*0.2:.1f},{0.01*i:.5f},,\n' for i in range(50)), 'scan', '50 rows of 2 numbers: a line profile')
put('ascii_size_no_unit.txt', '# Width: 40\n1 2 3\n4 5 6\n7 8 9\n', 'scan', 'states a size of 40 \'\' but no length unit')
put('ascii_trailing_text.txt', '# Width: 40 um\n# Value units: um\n1 2 3\n4 5 6um\n7 8 9\n', 'scan', "line 4, value 3: found '6um', expected a number")
put('ascii_counts.txt', 'x-pixels = 4\ny-pixels = 4\npixel size = 1 um\n1 2 3\n4 5 6\n7 8 9\n', 'scan', 'the header states 4 x 4 pixels; found 3 rows of 3 values')

# ---- hostile files: implausible data, special sizes, decompression bombs
t_x = [(i * 0.005, 2.85 * math.sin(2 * math.pi * i * 0.005)) for i in range(1000)]
def force_rows(fn): return csv(['time_s,x_mm,Q_N,P_N'] + [','.join(repr(v) for v in fn(i, t, x)) for i, (t, x) in enumerate(t_x)])
put('zero_load.csv', force_rows(lambda i, t, x: (t, x, 3.6, 0.0)), 'force', 'the normal force is 0 N at the median; expected a load')
put('huge_force.csv', force_rows(lambda i, t, x: (t, x, 1.7e308 if i == 500 else 3.6, 30.0)), 'force', 'sample 501 (t = 2.5 s): a force of 1.7e+308 N')
put('nm_stroke.csv', force_rows(lambda i, t, x: (t, x * 2e-6, 3.6, 30.0)), 'force', 'expected 0.05 to 50 mm for a reciprocating test')
put('um_as_mm.csv', force_rows(lambda i, t, x: (t, 1000 * x, 3.6, 30.0)), 'force', 'a stroke of 5697 mm (robust peak to peak of x)')
put('time_1e300.csv', force_rows(lambda i, t, x: (1e300 + t, x, 3.6, 30.0)), 'force', 'is not after the previous')
put('unequal_pitch.gsf', gsf('XRes = 4\nYRes = 4\nXReal = 0.03\nYReal = 3e-04\nXYUnits = mm\n', b'\0' * 64), 'scan', 'times longer one way than the other')
put('tiny_pitch.gsf', gsf('XRes = 4\nYRes = 4\nXReal = 3e-12\nYReal = 3e-12\nXYUnits = mm\n', b'\0' * 64), 'scan', 'expected 1e-06 to 100 mm')
put('keyence_huge_size.csv', 'XY Calibration,7.4,um\nHorizontal,1e30\nVertical,nan\nHeight\n1,2\n', 'scan', 'Horizontal = 1e30; expected a whole number of pixels')
# A VK4 whose conditions offset sits 156 bytes below 4 GiB: conditions + 168
# must not wrap to a small offset inside the file.
b = bytearray(vk4(2, 2, 32, 16, 16)); struct.pack_into('<I', b, 12, 0xFFFFFF64)
put('offset_wrap.vk4', bytes(b), 'scan', 'byte 4294967308: truncated: x length per pixel needs 4 bytes')
def zstd_rle(total, stated=True):
    """A zstd frame of `total` zero bytes in RLE blocks: a few bytes that
    expand to anything."""
    head = bytes([0xE0]) + struct.pack('<Q', total) if stated else bytes([0x00, 0x38])
    blocks, left = b'', total
    while left > 0:
        n = min(left, 128 * 1024); left -= n
        blocks += struct.pack('<I', (1 if left == 0 else 0) | (1 << 1) | (n << 3))[:3] + b'\0'
    return struct.pack('<I', 0xFD2FB528) + head + blocks
def zstd_raw(data):
    """A zstd frame holding `data` in one raw block, size stated."""
    return (struct.pack('<I', 0xFD2FB528) + bytes([0xE0]) + struct.pack('<Q', len(data)) +
            struct.pack('<I', 1 | (len(data) << 3))[:3] + data)
BOMB = 100 << 20  # 100 MiB
put('bomb_stated.zon', kpk({HG: zstd_rle(BOMB), CA: zstd_raw(CAL.encode())}, magic=b'KPK1'), 'scan', 'a ratio above 100 (a decompression bomb? --large-maps accepts it)')
put('bomb_stream.zon', kpk({HG: zstd_rle(BOMB, stated=False), CA: zstd_raw(CAL.encode())}, magic=b'KPK1'), 'scan', 'a ratio above 100 (a decompression bomb? --large-maps accepts it)')
put('bomb.x3p', x3p(main_xml(3620, 3620), {'bindata/data.bin': bytes(BOMB)}), 'scan', 'a ratio above 100 (a decompression bomb? --large-maps accepts it)')
vbuf = io.BytesIO()
with zipfile.ZipFile(vbuf, 'w') as z: z.writestr(entry('Vk4File', deflate=True), bytes(BOMB))
put('bomb.vk6', b'VK6' + struct.pack('<I', 2) + b'BM' + vbuf.getvalue(), 'scan', 'a ratio above 100 (a decompression bomb? --large-maps accepts it)')

put('binary_cell.csv', csv(good[:60] + ['\x01\x02\x1b[31mred,1,1,1'] + good[61:]), 'force', "line 61: found text '\\x01\\x02\\x1b[31mred' where a data row was expected")
put('binary_header_value.gsf', b'Gwyddion Simple Field 1.0\nXRes = 4\nYRes = \x01\x02\n\0\0\0\0' + b'\0' * 64, 'scan', "header line 3: YRes = '\\x01\\x02'; expected a positive pixel count")

whole = x3p(main_xml(4, 4), {'bindata/data.bin': b'\0' * 128})
put('truncated.x3p', whole[:len(whole) // 2], 'scan', 'no end-of-central-directory record in its last 64 KiB (the archive is')

# ---- Sensofar .plu (500-byte header, then rows, cols and float32 um)
def plu(rows, cols, pixels, kind=3, layers=1, pitch=1.66):
    b = bytearray(b'Mon Nov 23 05:00:00 2026'.ljust(128, b'\0') + b'\0' * 372)
    struct.pack_into('<3I7f', b, 388, rows, cols, cols, 1.0, pitch, pitch, 0, 0, pitch, 0)
    struct.pack_into('<5I', b, 428, kind, 0, 0, 0, 0)
    b[489] = layers
    return bytes(b) + struct.pack('<2I', rows, cols) + b'\0' * pixels
put('truncated.plu', plu(4, 4, 64)[:300], 'scan', 'truncated: the 508-byte PLU header needs 508 bytes')
put('profile.plu', plu(1, 4, 16, kind=1), 'scan', 'measurement type 1 (a profile); expected 3, a topography')
put('absurd.plu', plu(100000, 100000, 0), 'scan', 'a map of 100000 x 100000 points; expected 1 to 268435456 points')
put('short_data.plu', plu(4, 4, 10), 'scan', 'truncated: the heights needs 64 bytes')
put('no_layer.plu', plu(4, 4, 64, layers=0), 'scan', 'the file holds no layer')

# ---- Alicona .al3d (17-byte magic, 52-byte tags, float32 m)
def al3d(tags, data=b'', magic=b'AliconaImaging\x00\r\n', end=b'\r\n'):
    b = magic
    for k, v in tags:
        b += k.encode().ljust(20, b'\0') + str(v).encode().ljust(30, b'\0') + end
    return b + data
def al3d_tags(cols=4, rows=4, count=None, offset=None, skip=()):
    t = [('Cols', cols), ('Rows', rows), ('PixelSizeXMeter', 1e-6), ('PixelSizeYMeter', 1e-6),
         ('InvalidPixelValue', 'nan'), ('DepthImageOffset', offset if offset is not None else 17 + 52 * 8)]
    t = [x for x in t if x[0] not in skip]
    return [('Version', 1), ('TagCount', count if count is not None else len(t))] + t
put('bad_tag_end.al3d', al3d(al3d_tags(), b'\0' * 64, end=b'\n\n'), 'scan', 'a tag ends in')
put('tag_count.al3d', al3d(al3d_tags(count=999999999)), 'scan', "TagCount '999999999'; expected a whole number up to 4096")
put('no_cols.al3d', al3d(al3d_tags(skip=('Cols',)), b'\0' * 64), 'scan', 'no tag Cols; expected one in the header')
put('offset_outside.al3d', al3d(al3d_tags(offset=10 ** 9), b'\0' * 64), 'scan', 'DepthImageOffset 1000000000; expected a position inside the 497-byte file')
put('absurd.al3d', al3d(al3d_tags(cols=100000, rows=100000), b'\0' * 64), 'scan', 'a map of 100000 x 100000 points')
put('bad_magic.al3d', b'AliconaImagine\x00\r\n' + b'\0' * 200, 'scan', 'which is not the magic of a .al3d file')

# ---- Bruker/Veeco .opd (directory of 24-byte entries, blocks in its order)
def opd_entry(name, kind, length):
    return name.encode().ljust(16, b'\0') + struct.pack('<hlH', kind, length, 0)
def opd(nx, ny, elsize, payload, dir_len=None, blocks=None, wavelength=True):
    blocks = blocks if blocks is not None else [('RAW_DATA', 3, 6 + len(payload)), ('Pixel_size', 7, 4)] + ([('Wavelength', 7, 4)] if wavelength else [])
    entries = [('Directory', 1, dir_len if dir_len is not None else 24 * (len(blocks) + 1))] + blocks
    b = b'\x01\x00' + b''.join(opd_entry(*e) for e in entries)
    for name, kind, length in blocks:
        if name == 'RAW_DATA': b += struct.pack('<3H', nx, ny, elsize) + payload
        elif kind == 7: b += struct.pack('<f', 0.001 if name == 'Pixel_size' else 632.8)
        else: b += b'\0' * length
    return b
put('directory_length.opd', opd(4, 4, 2, b'\0' * 32, dir_len=25), 'scan', 'directory of 25 bytes; expected a positive multiple of 24')
put('no_array.opd', opd(4, 4, 2, b'', blocks=[('Wavelength', 7, 4)]), 'scan', 'the directory names no height array')
put('absurd.opd', opd(65535, 65535, 2, b''), 'scan', 'a map of 65535 x 65535 points')
put('block_size.opd', opd(4, 4, 2, b'\0' * 30), 'scan', 'an array of 4 x 4 x 2 bytes in a block of 36 bytes')
put('no_wavelength.opd', opd(4, 4, 2, b'\0' * 32, wavelength=False), 'scan', 'Wavelength 0 nm, Mult 1, Aspect 1, Pixel_size 0.001 mm; expected positive values')
put('bad_magic.opd', b'\x01\x00Directorz' + b'\0' * 100, 'scan', 'which is not the magic of a .opd file')

# ---- Digital Surf .sur (512-byte header; DSCOMPRESSED: zlib streams)
def sur(nx, ny, points=None, bits=32, kind=2, magic=b'DIGITAL SURF', data=None, csize=0, units=(b'um', b'um', b'um')):
    h = bytearray(512); h[0:12] = magic
    struct.pack_into('<hHhh', h, 12, 0, 1, 1, kind)
    struct.pack_into('<h', h, 98, bits)
    struct.pack_into('<5i', h, 100, 0, 1000, nx, ny, nx * ny if points is None else points)
    struct.pack_into('<3f', h, 120, 1.0, 1.0, 0.001)
    for i, u in enumerate(units): h[180 + 16 * i:180 + 16 * i + len(u)] = u
    struct.pack_into('<I', h, 324, csize)
    return bytes(h) + (data if data is not None else b'\0' * (nx * ny * bits // 8))
def sur_z(nx, ny, raw_stated, payload):
    z = zlib.compress(payload)
    block = struct.pack('<3I', 1, raw_stated, len(z)) + z
    return sur(nx, ny, magic=b'DSCOMPRESSED', data=block, csize=len(block))
import zlib
put('profile.sur', sur(4, 1, kind=1), 'scan', 'object type 1 (a profile); expected a surface (2, 11 or 16)')
put('bits.sur', sur(4, 4, bits=8), 'scan', '8 bits per point; expected 16 or 32')
put('points.sur', sur(4, 4, points=17), 'scan', '17 points in a map of 4 x 4; expected 16')
put('truncated.sur', sur(4, 4, data=b'\0' * 10), 'scan', 'truncated: the points needs 64 bytes')
put('unit.sur', sur(4, 4, units=(b'furlong', b'um', b'um')), 'scan', "x spacing 1 'furlong'; expected a positive number in m, mm, um or nm")
put('stream_size.sur', sur_z(4, 4, 60, b'\0' * 60), 'scan', 'the streams hold 60 bytes; the header')
put('stream_outside.sur', sur(4, 4, magic=b'DSCOMPRESSED', data=struct.pack('<3I', 1, 64, 10 ** 9) + b'x' * 8, csize=20), 'scan', 'truncated: a compressed stream needs 1000000000 bytes')
put('bomb.sur', sur_z(8192, 8192, 8192 * 8192 * 4, b'\0' * (8192 * 8192 * 4)), 'scan', 'a ratio above 100 (a decompression bomb? --large-maps accepts it)')
put('not_zlib.sur', sur(4, 4, magic=b'DSCOMPRESSED', data=struct.pack('<3I', 1, 64, 8) + b'notzlib!', csize=20), 'scan', 'not a zlib stream')
put('bad_magic.sur', b'DIGITAL SURG' + b'\0' * 600, 'scan', 'which is not the magic of a .sur file')

# ---- compressed as a whole (gzip, zstd)
import gzip
put('cut.csv.gz', gzip.compress(csv(good).encode(), mtime=0)[:300], 'force', 'gzip-compressed: the gzip data end after 300 bytes, cut short')
put('bomb.txt.gz', gzip.compress(b'0 ' * (40 << 20), mtime=0), 'scan', 'a ratio above 100 (a decompression bomb? --large-maps accepts it)')
put('corrupt.txt.zst', zstd_raw(b'1 2 3\n4 5 6\n7 8 9\n')[:9] + b'\xff' * 40, 'scan', '(zstd-compressed): corrupt zstd data')

# ---- Zygo MetroPro .dat (big-endian header of 834 bytes, intensity, phase)
def metropro(w, h, phase_bytes=None, header=834, phase_res=1, lateral=1e-6, data=None, magic=b'\x88\x1b\x03\x6f'):
    b = bytearray(834); b[0:4] = magic
    struct.pack_into('>HI', b, 4, 1, header)
    struct.pack_into('>HHI', b, 68, w, h, 4 * w * h if phase_bytes is None else phase_bytes)
    struct.pack_into('>4f', b, 164, 0.5, 6.328e-7, 0.0, 1.0)
    struct.pack_into('>f', b, 184, lateral)
    struct.pack_into('>h', b, 218, phase_res)
    return bytes(b) + (data if data is not None else b'\0' * (4 * w * h))
put('header_size.dat', metropro(4, 4, header=100), 'scan', 'header of 100 bytes; expected 834 or more')
put('phase_size.dat', metropro(4, 4, phase_bytes=60), 'scan', 'a phase block of 60 bytes for 4 x 4 points; expected 64')
put('phase_res.dat', metropro(4, 4, phase_res=7), 'scan', 'phase_res 7; expected 0, 1 or 2')
put('no_lateral.dat', metropro(4, 4, lateral=0.0), 'scan', 'lateral resolution 0 m per pixel')
put('truncated.dat', metropro(4, 4, data=b'\0' * 20), 'scan', 'truncated: the phase data needs 64 bytes')
put('no_phase.dat', metropro(0, 0), 'scan', 'the file holds no height data')

with open('catalogue.csv', 'w') as f:
    f.write('file,reader,expected\n')
    for name, kind, expected in rows:
        f.write(f'{name},{kind},"{expected}"\n')
print(len(rows), 'bad files')
