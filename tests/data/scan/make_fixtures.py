#!/usr/bin/env python3
"""Writes the small scan fixtures of the tests and fuzz seeds (run from this
folder). Layouts as in ../shared/FORMATS.md; values are simple ramps so a
reader's result is easy to check."""
import io, math, struct, zipfile

W, H = 8, 6
heights = [[round(1000 * math.sin(r + 0.5 * c)) for c in range(W)] for r in range(H)]

def grid(w, h, elem, stride, rows):
    out = struct.pack('<4i', w, h, elem, stride)
    for row in rows:
        b = b''.join(struct.pack('<i' if elem == 4 else '<B', v) for v in row)
        out += b + b'\0' * (stride - len(b))
    return out

def zon_zip():
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, 'w', zipfile.ZIP_DEFLATED) as z:
        z.writestr('4cdb0c75-5706-48cc-a9a1-adf395d609ae', grid(W, H, 4, 4 * W + 4, heights))
        mask = [[1 if (r, c) == (2, 3) else 0 for c in range(W)] for r in range(H)]
        z.writestr('9e7ca6dd-0e6a-4d7b-8986-f0a7b773c916', grid(W, H, 1, W, mask))
        z.writestr('686613b8-27b5-4a29-8ffc-438c2780873e',
                   '<Calibration><XYCalibration><MeterPerPixel>7.413e-6</MeterPerPixel>'
                   '</XYCalibration><ZCalibration><MeterPerUnit>1e-8</MeterPerUnit>'
                   '</ZCalibration></Calibration>')
        z.writestr('cbc1d39b-215f-4d56-a20e-cf8e5f570755',
                   '<Device><DeviceModelName>VR-6200</DeviceModelName></Device>')
    return buf.getvalue()

bmp = b'BM' + b'\0' * 14
zon = b'KPK0' + struct.pack('<I', len(bmp)) + bmp + zon_zip()
open('small.zon', 'wb').write(zon)
buf = io.BytesIO()
with zipfile.ZipFile(buf, 'w', zipfile.ZIP_STORED) as z:
    z.writestr('f1724dc6-686c-4502-9227-2a594bc8ed33', '<Inventory/>')
    z.writestr('item0/data/84b648d7-e44f-4909-ac11-0476720a67ff', zon)
    z.writestr('item1/data/84b648d7-e44f-4909-ac11-0476720a67ff', zon)
open('small.zag', 'wb').write(b'KPK0' + struct.pack('<I', 0) + buf.getvalue())

# VK4: header, offset table, measurement conditions (pm at 168/172/176),
# 32-bit height image with its 796-byte header.
vk4 = bytearray(b'VK4_' + b'\0' * 8 + b'\0' * 72)
cond = len(vk4)
vk4 += b'\0' * 200
struct.pack_into('<3I', vk4, cond + 168, 7413000, 7413000, 100)
img = len(vk4)
hdr = bytearray(796)
struct.pack_into('<5I', hdr, 0, W, H, 32, 0, W * H * 4)
vk4 += hdr + b''.join(struct.pack('<I', 100000 + v) for row in heights for v in row)
struct.pack_into('<I', vk4, 12, cond)
struct.pack_into('<I', vk4, 12 + 6 * 4, img)
open('small.vk4', 'wb').write(bytes(vk4))
buf = io.BytesIO()
with zipfile.ZipFile(buf, 'w', zipfile.ZIP_DEFLATED) as z:
    z.writestr('Vk4File', bytes(vk4))
open('small.vk6', 'wb').write(b'VK6' + struct.pack('<I', len(bmp)) + bmp + buf.getvalue())

# x3p: binary float64 with a valid.bin mask, nested in a folder, junk member.
buf = io.BytesIO()
data = b''.join(struct.pack('<d', v * 1e-9) for row in heights for v in row)
valid = bytearray(b'\xff' * ((W * H + 7) // 8)); valid[0] &= 0xfe
xml = f'''<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2"><Record1><Revision>ISO5436 - 2000</Revision>
<FeatureType>SUR</FeatureType><Axes><CX><AxisType>I</AxisType><DataType>D</DataType><Increment>7.4e-06</Increment>
<Offset>0</Offset></CX><CY><AxisType>I</AxisType><DataType>D</DataType><Increment>7.4e-06</Increment><Offset>0</Offset>
</CY><CZ><AxisType>A</AxisType><DataType>D</DataType></CZ></Axes></Record1><Record2><Date>2026-11-22T10:00:00</Date>
<Instrument><Manufacturer>wearscar</Manufacturer><Model>fixture</Model></Instrument></Record2>
<Record3><MatrixDimension><SizeX>{W}</SizeX><SizeY>{H}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
<DataLink><PointDataLink>bindata/data.bin</PointDataLink><ValidPointsLink>bindata/valid.bin</ValidPointsLink>
</DataLink></Record3></p:ISO5436_2>'''
with zipfile.ZipFile(buf, 'w', zipfile.ZIP_DEFLATED) as z:
    z.writestr('fixture/main.xml', xml)
    z.writestr('fixture/bindata/data.bin', data)
    z.writestr('fixture/bindata/valid.bin', bytes(valid))
    z.writestr('__MACOSX/fixture/._main.xml', b'junk')
open('small.x3p', 'wb').write(buf.getvalue())

# GSF (metres), Keyence VR CSV (mm), ASCII matrix (um).
head = f'Gwyddion Simple Field 1.0\nXRes = {W}\nYRes = {H}\nXReal = {W*7.4e-6}\nYReal = {H*7.4e-6}\nXYUnits = m\nZUnits = m\n'.encode()
head += b'\0' * (4 - len(head) % 4)
open('small.gsf', 'wb').write(head + b''.join(struct.pack('<f', v * 1e-9) for row in heights for v in row))
with open('keyence_small.csv', 'w') as f:
    f.write(f'"Measurement","VR-6200"\nHorizontal,{W}\nVertical,{H}\nXY Calibration,7.413,um\nUnit,mm\nHeight\n')
    for row in heights:
        f.write(','.join(f'{v * 1e-6:.6f}' for v in row) + '\n')
with open('small.txt', 'w') as f:
    f.write('# ascii matrix, um\n')
    for row in heights:
        f.write(' '.join(f'{v * 1e-3:.3f}' for v in row) + '\n')
