"""The rounding and saturation events of each vector, from the model itself: every vector of
a datapath block is replayed through the block's live reference in build/libc5ref.so (the
model's own block function, built with the probe of rtl_model/proc/round_probe.h), and the events
each site met are read back. The replay must give the vector's own outputs, or the events
would belong to another computation: a mismatch is an error, never a silent miss.

Used by vectors_coverage.py: Probe(lib).events(block, vals, images) -> {site: bits}."""
import ctypes, os

# C5_EV_* of rtl_model/proc/round_probe.h: the names the coverage points take.
EVENTS = {'exact': 1, 'down': 2, 'up': 4, 'tie_kept': 8, 'tie_up': 16, 'sat_lo': 32, 'sat_hi': 64}


class ProbeError(Exception):
    pass


def read_image(path):
    """An image file's lines as lists of raw column values."""
    with open(path) as f:
        return [[int(c, 16) for c in line.split()] for line in f]


def s32(x):
    """A 32-bit image word as the signed integer the registers hold."""
    return x - (1 << 32) if x >> 31 else x


class Probe:
    def __init__(self, lib_path):
        try:
            self.lib = ctypes.CDLL(os.path.abspath(lib_path))
        except OSError as e:
            raise ProbeError(f'{lib_path}: {e} (make {lib_path} builds it)')
        L = self.lib
        L.c5ref_probe_site_name.restype = ctypes.c_char_p
        self.sites = [L.c5ref_probe_site_name(i).decode() for i in range(L.c5ref_probe_sites())]
        self.loaded = {}  # image kind -> the file loaded into the reference

    def _load(self, kind, path, put):
        if self.loaded.get(kind) != path:
            for i, cols in enumerate(read_image(path)):
                put(i, cols)
            self.loaded[kind] = path

    def events(self, block, v, out_names, images):
        """{site: event bits} of one vector of `block` (v: field name -> value, signed fields
        negative); raises ProbeError when the reference's outputs differ from the vector's.
        None for a block without rounding sites."""
        L = self.lib
        run = getattr(self, '_' + block, None)
        if run is None:
            return None
        L.c5ref_probe_reset()
        got = run(v, images)
        want = {n: v[n] for n in out_names}
        if got != want:
            diff = [f'{n}: vector {want[n]} model {got[n]}' for n in want if got[n] != want[n]]
            raise ProbeError(f'{block}: the model replayed gives other outputs ({"; ".join(diff)})')
        seen = {}
        for i, name in enumerate(self.sites):
            bits = L.c5ref_probe_seen(i)
            if bits and i == 0:
                raise ProbeError(f'{block}: a rounding without a site (rtl_model/proc/round_probe.h)')
            if bits:
                seen[name] = bits
        return seen

    # One replay per block: the inputs as the VHDL testbench drives them, the outputs read
    # back under the vector's field names (fpga/ref/c5ref_*.c).
    def _interp(self, v, images):
        args = [v['frac_x'], v['frac_y'], v['frac_z']] + [v[f'v{k}'] for k in range(8)]
        return {'value': self.lib.c5ref_interp(*args)}

    def _gradient(self, v, images):
        L = self.lib
        for k, n in enumerate(['frac_x', 'frac_y', 'frac_z']):
            L.c5ref_gr_set(k, v[n])
        for a, ax in enumerate('xyz'):
            for c in range(8):
                L.c5ref_gr_set(3 + 8 * a + c, v[f'd{ax}{c}'])
            L.c5ref_gr_set(27 + a, v[f'gs_{ax}'])
        return {f'grad_{ax}': L.c5ref_gr_run(a) for a, ax in enumerate('xyz')}

    def _classify(self, v, images):
        L = self.lib
        self._load('tf', images['tf'],
                   lambda i, cols: [L.c5ref_cl_table(i, ch, cols[ch]) for ch in range(4)])
        return {ch: L.c5ref_cl_run(v['value'], k) for k, ch in enumerate('rgba')}

    def _shade(self, v, images):
        L = self.lib
        self._load('regs', images['regs'], lambda i, cols: L.c5ref_sh_reg_set(i, s32(cols[0])))
        self._load('pow', images['pow'], lambda i, cols: L.c5ref_sh_pow_set(i, cols[0]))
        ins = [f'grad_{a}' for a in 'xyz'] + [f'tf_{c}' for c in 'rgb'] + [f'gpos_{a}' for a in 'xyz'] + \
            [f'dir_{a}' for a in 'xyz']
        for k, n in enumerate(ins):
            L.c5ref_sh_set(k, v[n])
        L.c5ref_sh_run(-1)
        out = {f'rgb_{c}': L.c5ref_sh_run(k) for k, c in enumerate('rgb')}
        out['sat'] = L.c5ref_sh_run(3)
        return out

    def _composite(self, v, images):
        L = self.lib
        ins = ['w', 'opa', 'rgb_r', 'rgb_g', 'rgb_b', 'alpha', 'c_r', 'c_g', 'c_b', 'shadow', 'a_max']
        for k, n in enumerate(ins):
            L.c5ref_cp_set(k, v[n])
        L.c5ref_cp_run()
        outs = ['rgb_r_out', 'rgb_g_out', 'rgb_b_out', 'opa_out', 'done', 'sat']
        return {n: L.c5ref_cp_out(k) for k, n in enumerate(outs)}
