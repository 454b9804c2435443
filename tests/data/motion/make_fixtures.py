#!/usr/bin/env python3
"""Writes the motion test fixtures (no numpy needed): SMPL-H npz archives laid out as
HY-Motion-1.0 (np.savez_compressed: DEFLATE members with zip64 local headers) and AMASS
(np.savez: stored) write them, and the binary part of the malformed-input corpus in bad/.
Run from this directory: python3 make_fixtures.py. Output is deterministic."""
import math
import pickle
import struct
import zipfile

def npy(shape, values, descr='<f8', fortran=False, version=1):
    dims = ', '.join(str(d) for d in shape) + (',' if len(shape) == 1 else '')
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': (%s), }" % (descr, 'True' if fortran else 'False', dims)
    pre = 10 if version == 1 else 12
    header += ' ' * ((64 - (pre + len(header) + 1) % 64) % 64) + '\n'
    out = b'\x93NUMPY' + bytes([version, 0])
    out += struct.pack('<H' if version == 1 else '<I', len(header)) + header.encode('latin1')
    if descr == '|O':
        return out + pickle.dumps(values, protocol=2)
    if descr.endswith('U7'):
        return out + ''.join(values).ljust(7, '\0').encode('utf-32-le')
    fmt = {'<f8': '<d', '<f4': '<f', '>f8': '>d', '<i8': '<q', '<i2': '<h', '<c16': '<dd'}[descr]
    if descr == '<c16':
        return out + b''.join(struct.pack(fmt, v, 0.0) for v in values)
    return out + b''.join(struct.pack(fmt, v) for v in values)

def write_zip(path, members, deflate):
    with zipfile.ZipFile(path, 'w', zipfile.ZIP_DEFLATED if deflate else zipfile.ZIP_STORED) as z:
        for name, data in members:
            info = zipfile.ZipInfo(name + '.npy', date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED if deflate else zipfile.ZIP_STORED
            with z.open(info, 'w', force_zip64=True) as f:  # as numpy's savez does
                f.write(data)

F = 3
def poses_of(per_frame):
    out = []
    for f in range(F):
        row = [0.0] * 156
        for j, v in per_frame(f).items():
            row[3 * j:3 * j + 3] = v
        out += row
    return out

# HY-Motion-like (y-up): frame 0 the T-pose; frames 1-2 the left arm raised (shoulder +z
# rotation: +x -> +y), walking 0.1 m per frame along +z (the way the body faces).
hy_poses = poses_of(lambda f: {} if f == 0 else {16: [0.0, 0.0, math.pi / 2]})
hy_trans = [v for f in range(F) for v in (0.0, 0.95, 0.1 * f)]
write_zip('hy_motion_like.npz', [
    ('gender', npy((), ['neutral'], descr='<U7')),
    ('Rh', npy((F, 3), [v for f in range(F) for v in hy_poses[156 * f:156 * f + 3]])),
    ('trans', npy((F, 3), hy_trans)),
    ('poses', npy((F, 156), hy_poses)),
    ('betas', npy((1, 16), [0.0] * 16)),
], deflate=True)

# AMASS-like (z-up): root_orient = +90 deg about x (SMPL's y-up body stands up in z), so the
# body faces world -y; 60 fps; a pickled object member that must not be decoded.
amass_poses = poses_of(lambda f: {0: [math.pi / 2, 0.0, 0.0]})
write_zip('amass_like.npz', [
    ('poses', npy((F, 156), amass_poses)),
    ('trans', npy((F, 3), [v for f in range(F) for v in (0.0, -0.01 * f, 0.95)])),
    ('betas', npy((16,), [0.0] * 16)),
    ('mocap_framerate', npy((), [60.0])),
    ('dmpls', npy((F, 8), [0.0] * (8 * F))),
    ('marker_labels', npy((2,), ['a', 'b'], descr='|O')),
], deflate=False)

# ---- malformed corpus (binary part) --------------------------------------------------------
good = npy((2, 22, 3), [0.1 * i for i in range(132)], descr='<f4')
def put(name, data):
    with open('bad/' + name, 'wb') as f:
        f.write(data)
put('npy_wrong_joint_count.npy', npy((2, 21, 3), [0.0] * 126, descr='<f4'))
put('npy_unsupported_dtype.npy', npy((2, 22, 3), [0] * 132, descr='<i2'))
put('npy_complex_dtype.npy', npy((1, 22, 3), [0.0] * 66, descr='<c16'))
put('npy_fortran_order.npy', npy((2, 22, 3), [0.0] * 132, descr='<f4', fortran=True))
put('npy_truncated_data.npy', good[:-10])
put('npy_bad_magic.npy', b'NUMPY!' + good[6:])
put('npy_bad_header.npy', good.replace(b"'shape': (2, 22, 3)", b"'shape': [2, 22, 3]"))
put('npy_truncated_header.npy', good[:40])
put('npy_nan_value.npy', npy((2, 22, 3), [0.0] * 70 + [float('nan')] + [0.0] * 61, descr='<f4'))
put('npy_pickled_objects.npy', npy((2,), [{'a': 1}, 'x'], descr='|O'))
put('npz_not_a_zip.npz', b'this is not a zip archive, just some text pretending to be an npz file\n')
members = [('trans', npy((F, 3), hy_trans)), ('poses', npy((F, 156), hy_poses))]
write_zip('bad/npz_missing_poses.npz', members[:1], deflate=True)
write_zip('bad/npz_pickled_poses.npz', [members[0], ('poses', npy((F,), ['a', 'b', 'c'], descr='|O'))], deflate=False)
write_zip('bad/npz_poses_wrong_shape.npz', [members[0], ('poses', npy((F, 10), [0.0] * (10 * F)))], deflate=False)
write_zip('bad/npz_inf_trans.npz', [('trans', npy((F, 3), [0.0, float('inf')] + [0.0] * 7)), members[1]], deflate=False)
# Corrupted DEFLATE stream: the first block header says "type 3" (reserved).
write_zip('bad/npz_corrupt_deflate.npz', members, deflate=True)
with open('bad/npz_corrupt_deflate.npz', 'rb') as f:
    data = bytearray(f.read())
lh = data.index(b'PK\x03\x04', data.index(b'poses.npy') - 30)
start = lh + 30 + struct.unpack('<H', data[lh + 26:lh + 28])[0] + struct.unpack('<H', data[lh + 28:lh + 30])[0]
data[start] = (data[start] & ~0x07) | 0x07
put('npz_corrupt_deflate.npz', bytes(data))
# A stored member with one data byte flipped: CRC mismatch.
write_zip('bad/npz_bad_crc.npz', members, deflate=False)
with open('bad/npz_bad_crc.npz', 'rb') as f:
    data = bytearray(f.read())
data[data.index(b'poses.npy') + 9 + 200] ^= 0xFF
put('npz_bad_crc.npz', bytes(data))
with open('hy_motion_like.npz', 'rb') as f:
    whole = f.read()
put('npz_truncated.npz', whole[:len(whole) // 2])
