#!/usr/bin/env python3
"""tests/fuzz/make_seeds.py: writes the hand-made seed inputs of the fuzz
targets into tests/fuzz/corpus/NAME/ (run from the repository root; the files
are committed, this script shows how each was made).  Every seed is small and
of our own making: a valid input of the format, plus edge cases (truncated,
absurd sizes, NaN, missing fields).  Regression inputs found by fuzzing are
added beside them as regress-*.  Three seeds are files pp5 itself wrote, copied in
by hand: volume_nrrd/pp5-written-phantom-4x4x3 (`pp5 volume phantom sphere-shell
--size 4x4x3`, after the byte that picks .nrrd), trace_read/pp5-synth-saccades
(`pp5 trace synth --mode saccades --seconds 0.03`) and trace_read/umockdev-recording
(tests/fixtures/devices/eyetracker-20.trace)."""
import gzip, os, struct

ROOT = 'tests/fuzz/corpus'

def put(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode('latin-1')
    with open(os.path.join(d, name), 'wb') as f:
        f.write(data)

def gz(data):
    if isinstance(data, str):
        data = data.encode()
    return gzip.compress(data, mtime=0)

# ---- raw with header: 4 layout bytes (see fuzz_volume_raw.c), then the file
def raw_spec(nx, ny, nz, vtype, big, header):
    return bytes([(nx - 1) | (ny - 1) << 4, (nz - 1) | vtype << 4, 1 if big else 0, header])
put('volume_raw', 'u8-2x2x2', raw_spec(2, 2, 2, 0, False, 0) + bytes(range(8)))
put('volume_raw', 'u16be-2x2x1-header4', raw_spec(2, 2, 1, 2, True, 4) + b'HDR!' +
    struct.pack('>4H', 1, 2, 300, 65535))
put('volume_raw', 'f32-nan', raw_spec(2, 1, 1, 6, False, 0) + struct.pack('<2f', 1.5, float('nan')))
put('volume_raw', 'f64-huge', raw_spec(1, 1, 1, 7, False, 0) + struct.pack('<d', 1e300))
put('volume_raw', 'u8-truncated', raw_spec(4, 4, 4, 0, False, 0) + bytes(10))
put('volume_raw', 'u8-gzip', raw_spec(4, 4, 2, 0, False, 0) + gz(bytes(range(32))))
put('volume_raw', 'gzip-truncated', raw_spec(4, 4, 2, 0, False, 0) + gz(bytes(range(32)))[:20])

# ---- NRRD: first byte even = attached .nrrd, odd = detached .nhdr
hdr = ('NRRD0004\n# pp5 fuzz seed\ntype: unsigned char\ndimension: 3\nsizes: 2 2 2\n'
       'spacings: 1 1 2.5\nencoding: raw\n\n')
put('volume_nrrd', 'attached-raw-u8', b'\0' + hdr.encode() + bytes(range(8)))
put('volume_nrrd', 'attached-ascii-f32', b'\0' + b'NRRD0004\ntype: float\ndimension: 3\n'
    b'sizes: 2 1 1\nencoding: ascii\n\n1.5 -2\n')
put('volume_nrrd', 'attached-gzip-i16', b'\0' + b'NRRD0005\ntype: short\ndimension: 3\n'
    b'sizes: 2 2 1\nendian: big\nencoding: gzip\n\n' + gz(struct.pack('>4h', -1, 2, 3, 4)))
put('volume_nrrd', 'attached-4d-leading-1', b'\0' + b'NRRD0004\ntype: uchar\ndimension: 4\n'
    b'sizes: 1 2 2 1\nencoding: raw\n\n' + bytes(4))
put('volume_nrrd', 'space-directions', b'\0' + b'NRRD0005\ntype: uchar\ndimension: 3\n'
    b'space: left-posterior-superior\nsizes: 2 2 2\n'
    b'space directions: (0.5,0,0) (0,0.5,0) (0,0,2)\nspace origin: (0,0,0)\nencoding: raw\n\n'
    + bytes(8))
put('volume_nrrd', 'absurd-sizes', b'\0' + b'NRRD0004\ntype: double\ndimension: 3\n'
    b'sizes: 2147483648 2147483648 2\nencoding: raw\n\n')
put('volume_nrrd', 'detached-one-file', b'\1' + b'NRRD0004\ntype: uchar\ndimension: 3\n'
    b'sizes: 4 4 4\nencoding: raw\ndata file: data.raw\nbyte skip: 16\n')
put('volume_nrrd', 'detached-list', b'\1' + b'NRRD0004\ntype: uchar\ndimension: 3\n'
    b'sizes: 8 8 2\nencoding: raw\ndata file: LIST\ndata.raw\ndata.raw\n')
put('volume_nrrd', 'detached-pattern', b'\1' + b'NRRD0004\ntype: uchar\ndimension: 3\n'
    b'sizes: 4 4 2\nencoding: raw\ndata file: data.%03d 1 2 1\n')
put('volume_nrrd', 'detached-pattern-two-billion', b'\1' + b'NRRD0004\ntype: uchar\n'
    b'dimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: d%d.raw 1 2000000000 1 2\n')
put('volume_nrrd', 'detached-circular', b'\1' + b'NRRD0004\ntype: uchar\ndimension: 3\n'
    b'sizes: 2 2 2\nencoding: raw\ndata file: volume.nhdr\n')
put('volume_nrrd', 'detached-format-attack', b'\1' + b'NRRD0004\ntype: uchar\n'
    b'dimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: %s%n%d 1 2 1\n')

# ---- NIfTI-1: 348-byte header, 4 extension bytes, data at 352
def nifti(dims, datatype, bitpix, data, slope=0.0, big=False, magic=b'n+1\0'):
    e = '>' if big else '<'
    h = bytearray(348)
    struct.pack_into(e + 'i', h, 0, 348)
    dim = [len(dims)] + list(dims) + [1] * (7 - len(dims))
    struct.pack_into(e + '8h', h, 40, *dim)
    struct.pack_into(e + 'hh', h, 70, datatype, bitpix)
    struct.pack_into(e + '8f', h, 76, 1, 1, 1, 2, 0, 0, 0, 0)
    struct.pack_into(e + 'f', h, 108, 352.0)
    struct.pack_into(e + 'ff', h, 112, slope, 0.0)
    h[344:348] = magic
    return bytes(h) + bytes(4) + data
put('volume_nifti', 'u8-2x2x2', nifti((2, 2, 2), 2, 8, bytes(range(8))))
put('volume_nifti', 'i16-be-slope', nifti((2, 2, 1), 4, 16, struct.pack('>4h', -5, 0, 5, 9),
                                          slope=2.0, big=True))
put('volume_nifti', 'f32-2d', nifti((2, 2), 16, 32, struct.pack('<4f', 0, 1, 2, float('inf'))))
put('volume_nifti', 'time-series', nifti((2, 1, 1, 3), 2, 8, bytes(6)))
put('volume_nifti', 'truncated', nifti((4, 4, 4), 2, 8, bytes(10)))
put('volume_nifti', 'u8-gzip', gz(nifti((2, 2, 2), 2, 8, bytes(range(8)))))
put('volume_nifti', 'bad-magic', nifti((2, 2, 2), 2, 8, bytes(8), magic=b'xx1\0'))

# ---- VolPack .den: 62-byte header (see render/volume_den.c)
def den(map_len, data, big=False, version=1, length=None):
    e = '>' if big else '<'
    vals = [version]
    for box in range(3):
        vals += [0, 0, 0] + [n - 1 for n in map_len] + list(map_len)
    vals += [3]
    n = map_len[0] * map_len[1] * map_len[2]
    return struct.pack(e + '29hi', *vals, n if length is None else length) + data
put('volume_den', 'u8-2x2x2', den((2, 2, 2), bytes(range(8))))
put('volume_den', 'big-endian', den((2, 1, 3), bytes(6), big=True))
put('volume_den', 'length-mismatch', den((2, 2, 2), bytes(8), length=9))
put('volume_den', 'too-long', den((2, 2, 2), bytes(9)))
put('volume_den', 'absurd', den((4096, 4096, 4096), b'', length=-1))

# ---- slice series: byte N (slices - 1 in the low bits, bit 7: start at 0),
# then the slices separated by "\xffSLC"
SEP = b'\xffSLC'
put('volume_slices', 'two-2x2-slices', bytes([1]) + struct.pack('>4H', 1, 2, 3, 4) + SEP +
    struct.pack('>4H', 5, 6, 7, 8))
put('volume_slices', 'three-from-0', bytes([0x82]) + SEP.join([bytes(8)] * 3))
put('volume_slices', 'unequal', bytes([1]) + bytes(8) + SEP + bytes(18))
put('volume_slices', 'not-square', bytes([0]) + bytes(6))

# ---- pp5 traces
TRACE = ('# pp5-trace v1\n# source: fuzz seed\n# tracker: synthetic\n# sample_rate_hz: 500\n'
         '# screen_px: 1280 1024\n# screen_mm: 340 270\n# distance_mm: 600\n'
         't_ms\tx_px\ty_px\tstatus\tlabel\n0\t640\t512\tok\t1\n2\t641.5\t512.25\tok\t1\n'
         '4\tnan\tnan\tblink\t5\n6\tnan\tnan\tlost\t0\n# end: 4 samples\n')
put('trace_read', 'basic', TRACE)
put('trace_read', 'killed-recording', TRACE[:TRACE.index('# end')])
put('trace_read', 'pose-columns', '# pp5-trace v1\n# source: s\n# sample_rate_hz: 120\n'
    '# screen_px: 100 100\n# screen_mm: unknown\n# distance_mm: unknown\n# px_per_deg: 10\n'
    't_ms\tx_px\ty_px\tstatus\tlabel\thead_x_mm\thead_y_mm\thead_z_mm\thead_az_deg\t'
    'head_el_deg\thead_roll_deg\n0\t1\t2\tok\t0\t1\t2\t3\t4\t5\t6\n'
    '8.333333\t1\t2\tok\t0\tnan\tnan\tnan\tnan\tnan\tnan\n')
put('trace_read', 'backwards-time', TRACE.replace('\n2\t641.5', '\n-2\t641.5'))
put('trace_read', 'nul-byte', TRACE.replace('fuzz seed', 'fuzz\0seed'))

# ---- importers
put('import_eyelink', 'binocular-500hz', '** CONVERTED FROM x.edf\n'
    'MSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\n'
    'SAMPLES\tGAZE\tLEFT\tRIGHT\tRATE\t500.00\tTRACKING\tCR\tFILTER\t2\n'
    '10\t 512.0\t 384.0\t 900.0\t 520.0\t 380.0\t 910.0\t.....\n'
    '12\t   .\t   .\t    0.0\t 521.0\t 381.0\t 905.0\t.C...\n'
    'SBLINK L 12\nEBLINK L 12 14 2\n14\t   .\t   .\t    0.0\t   .\t   .\t    0.0\t.....\n'
    'EFIX R 10 12 4 520 380 910\nEND\t16 \tSAMPLES\tEVENTS\tRES\t 35.0\t 36.0\n')
put('import_eyelink', 'mono-2000hz-same-stamp', '** CONVERTED\n'
    'MSG\t1 GAZE_COORDS 0.00 0.00 640.00 480.00\nSTART\t1 \tRIGHT\tSAMPLES\tEVENTS\n'
    'SAMPLES\tGAZE\tRIGHT\tRATE\t2000.00\n5\t100.0\t200.0\t1000.0\t...\n'
    '5\t101.0\t201.0\t1000.0\t...\n6\tNaN\tNaN\t0.0\t...\nESACC R 5 6 2 100 200 101 201 0.1 20\n'
    'END\t7 \tSAMPLES\tEVENTS\tRES\t 25.0\t 25.0\n')
put('import_eyelink', 'href-samples', '**\nSTART\t1 \tLEFT\tSAMPLES\nSAMPLES\tHREF\tLEFT\tRATE\t'
    '250\n1\t1\t2\t3\n')
put('import_eyelink', 'sample-outside-block', '**\n1\t2\t3\t4\n')
put('import_tobii', 'pro-lab-ms', 'Recording timestamp [ms]\tSensor\tGaze point X\tGaze point Y\t'
    'Validity left\tValidity right\tEye movement type\n0\tEye Tracker\t960\t540\tValid\tValid\t'
    'Fixation\n8\tEye Tracker\t961\t541\tValid\tInvalid\tFixation\n16\tEye Tracker\t\t\tInvalid\t'
    'Invalid\tEyesNotFound\n20\tGyroscope\t\t\t\t\t\n24\tEye Tracker\t962,5\t542\tValid\tValid\t'
    'Saccade\n')
put('import_tobii', 'pro-lab-us', 'Recording timestamp [\u03bcs]\tGaze point X\tGaze point Y\n'
    '0\t1\t2\n20000\t3\t4\n40000\t5\t6\n'.encode('utf-8').decode('latin-1'))
put('import_tobii', 'sdk3-tx300', 'Time\tLGazePos2dx\tLGazePos2dy\tLValidity\tRGazePos2dx\t'
    'RGazePos2dy\tRValidity\n100\t0.5\t0.5\t0\t0.4\t0.4\t1\n3433\t-1\t-1\t4\t0.4\t0.4\t0\n'
    '6766\t0.6\t0.6\t0\t0.6\t0.6\t0\n')
put('import_pupil', 'gaze-positions', 'gaze_timestamp,world_index,confidence,norm_pos_x,'
    'norm_pos_y,base_data\n1.000,0,0.95,0.5,0.5,"1.0-0 1.0-1"\n1.004,0,0.30,0.5,0.5,"x,y"\n'
    '1.004,0,0.99,0.25,0.75,\n1.008,1,0.90,nan,0.5,\n')
put('import_pupil', 'surface', 'world_timestamp,world_index,gaze_timestamp,x_norm,y_norm,'
    'x_scaled,y_scaled,on_surf,confidence\n1,0,1.0,0.5,0.5,1,1,True,0.9\n'
    '1,0,1.005,0.6,0.4,1,1,False,0.9\n1,0,1.010,0.7,0.3,1,1,True,0.9\n')
put('import_shared', 'basic', '# gaze-trace v1\n# source: fuzz seed\n# sample_rate_hz: 500 Hz\n'
    '# screen_px: 1280 1024 (from DISPLAY_COORDS)\n# screen_mm: 340 270\n# distance_mm: 600\n'
    't_ms\tx_px\ty_px\tlabel\tblock\n0\t640\t512\t1\t0\n2\t641\t513\t1\t0\n4\tnan\tnan\t5\t0\n')
put('import_shared', 'px-per-deg', '# gaze-trace v1\n# source: s\n# sample_rate_hz: 60\n'
    '# screen_px: 10 10\n# screen_mm: unknown\n# distance_mm: unknown\n'
    '# eyelink_res_px_per_deg: 35.1 36.0\nt_ms\tx_px\ty_px\n0\t1\t1\n16.7\t2\t2\n')

# ---- machine configuration
put('params_config', 'defaults-subset', '# pp5 machine parameters\nring.channels = 8\n'
    'gp.count = 16   # graphics processors\n\nrenderer.count = 16\n')
put('params_config', 'bad-value', 'ring.channels = eight\n')
put('params_config', 'unknown-key', 'ring.nothing = 1\n')
put('params_config', 'out-of-range', 'gp.count = 100000\n')
put('params_set', 'one', 'ring.channels=4')
put('params_set', 'several', 'gp.count=8\nring.channels=2\nrenderer.count=4')
put('params_set', 'spaces-and-junk', ' ring.channels = 4 \n=\nring.channels=\n=5\nx=y=z')
put('params_set', 'float', 'gp.clock_hz=4e7\ngp.clock_hz=nan\ngp.clock_hz=1e400')

# ---- HID: pp5's eye tracker descriptor (tests/fixtures/devices/eye_tracker_desc.h)
def fixture_descriptor():
    text = open('tests/fixtures/devices/eye_tracker_desc.h').read()
    body = text[text.index('{', text.index('pp5_fixture_eye_desc')) + 1:]
    body = body[:body.index('}')]
    out = []
    for line in body.split('\n'):
        line = line.split('//')[0]
        while '/*' in line and '*/' in line:
            line = line[:line.index('/*')] + line[line.index('*/') + 2:]
        out += [int(tok, 16) for tok in line.replace(',', ' ').split() if tok.startswith('0x')]
    return bytes(out)
desc = fixture_descriptor()
put('hid_desc', 'eye-tracker', desc)
put('hid_desc', 'eye-tracker-truncated', desc[:len(desc) // 2])
put('hid_desc', 'mouse', bytes.fromhex('05010902a1010901a100050919012903150025019503750181029501'
                                       '750581030501093009311581257f750895028106c0c0'))
put('hid_desc', 'push-pop-long-item', bytes.fromhex('a40512b409010a0100fe0301020304a101c0'))
put('hid_desc', 'deep-collections', bytes([0xa1, 0x01] * 20 + [0xc0] * 20))

def tracking_report(ts, x, y):
    r = bytearray(65)
    r[0] = 0x10
    struct.pack_into('<Q', r, 1, ts)
    struct.pack_into('<ii', r, 9, x, y)
    return bytes(r)
reports = [tracking_report(1000, 263520, -148230), tracking_report(2000, 2000001, 0),
           bytes.fromhex('1101d0dd060010eb0900f07e0e00c027090020300500'),
           bytes.fromhex('12ac10b1a04e61bc00e107c00a08000c860400'), bytes.fromhex('1301fa00'),
           tracking_report(3000, 1, 2)[:30]]
put('hid_report', 'eye-tracker-reports', struct.pack('<H', len(desc)) + desc +
    b''.join(bytes([len(r)]) + r for r in reports))

# ---- Polhemus: 8-byte header ("PA"/"LY", station, command, error, reserved,
# payload size LE) + 6 LE floats (+ CR LF)
def pol(tag, station, vals, crlf=False):
    payload = struct.pack('<6f', *vals) + (b'\r\n' if crlf else b'')
    return tag + bytes([station, ord('P'), 0, 0]) + struct.pack('<H', len(payload)) + payload
put('polhemus', 'patriot-two-stations', pol(b'PA', 1, [1, 2, 3, 90, 0, -45]) +
    pol(b'PA', 2, [4, 5, 6, 0, 10, 0]))
put('polhemus', 'liberty-crlf', pol(b'LY', 1, [1, 2, 3, 4, 5, 6], crlf=True))
put('polhemus', 'latus-lu', pol(b'LU', 3, [0] * 6))
put('polhemus', 'nan', pol(b'PA', 1, [float('nan')] + [0] * 5))
put('polhemus', 'truncated', pol(b'PA', 1, [1] * 6)[:20])

# ---- Fastrak: format byte (values - 1 | 16 trailing space | 32 ASCII), stream
def fbin(station, status, vals, space=True):
    return b'0' + bytes([ord('0') + station, ord(status)]) + struct.pack('<%df' % len(vals), *vals) \
        + (b' ' if space else b'')
put('fastrak', 'binary-two-records', bytes([5 | 16]) + b'xx' + fbin(1, ' ', [10, -2.5, 30.25, 5, -100, 0.5]) +
    fbin(2, 'B', [35, 12, 20, 90, 0, -45]))
put('fastrak', 'binary-bad-status', bytes([5 | 16]) + fbin(1, 'z', [0] * 6))
put('fastrak', 'ascii-two-records', bytes([5 | 32]) +
    b'01   10.00  -2.50  30.25   5.00-100.00   0.50\r\n'
    b'02A  35.00  12.00  20.00  90.00   0.00 -45.00\r\n')
put('fastrak', 'ascii-missing-crlf', bytes([5 | 32]) + b'01   10.00  -2.50')
