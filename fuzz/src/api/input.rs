//! Reads the arguments of one call from the fuzz input. Past the end every read gives 0,
//! and 0 always means the ordinary, valid choice, so short inputs make good calls.

/// The argument bytes of one operation.
pub struct Input<'a> {
    bytes: &'a [u8],
    at: usize,
}

/// Floats that break naive code: NaN, infinities, extremes, subnormals, signed zero.
const SPECIAL: [f32; 16] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MAX,
    f32::MIN,
    1.0e30,
    -1.0e30,
    1.0e-30,
    1.0e-40,
    f32::MIN_POSITIVE,
    -0.0,
    1.0e7,
    -1.0e7,
    f32::EPSILON,
    3.0e38,
    -1.0e-7,
];

impl<'a> Input<'a> {
    pub fn new(bytes: &'a [u8]) -> Input<'a> {
        Input { bytes, at: 0 }
    }

    pub fn byte(&mut self) -> u8 {
        let byte = self.bytes.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        byte
    }

    /// A value in `0..n` (`n` at most 256).
    pub fn below(&mut self, n: u32) -> u32 {
        u32::from(self.byte()) % n
    }

    /// True one time in sixteen: take the unusual branch (a bad argument).
    pub fn rare(&mut self) -> bool {
        self.byte() >= 0xF0
    }

    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.byte(), self.byte(), self.byte(), self.byte()])
    }

    pub fn u64(&mut self) -> u64 {
        u64::from(self.u32()) | u64::from(self.u32()) << 32
    }

    /// A float: mostly in [-14, 14) in steps of 1/8 (0 for a zero byte), one time in
    /// sixteen a special value, rarely any bit pattern.
    pub fn float(&mut self) -> f32 {
        match self.byte() {
            byte @ 0xF0.. => SPECIAL[usize::from(byte - 0xF0)],
            0xEF => f32::from_bits(self.u32()),
            byte => f32::from(byte as i8) / 8.0,
        }
    }

    /// `usual` unless the input asks for a bad value, then any float.
    pub fn float_or(&mut self, usual: f32) -> f32 {
        if self.rare() {
            self.float()
        } else {
            usual
        }
    }

    /// A positive float in (0, 8], or rarely any float.
    pub fn positive(&mut self) -> f32 {
        if self.rare() {
            self.float()
        } else {
            f32::from(self.byte()) / 32.0 + 1.0 / 32.0
        }
    }

    /// A `struct_size`: mostly the right one, rarely 0, 3, one field short, one field
    /// long or `u32::MAX`.
    pub fn struct_size(&mut self, right: usize) -> u32 {
        let right = right as u32;
        if !self.rare() {
            return right;
        }
        match self.below(5) {
            0 => 0,
            1 => 3,
            2 => right - 4,
            3 => right + 4,
            _ => u32::MAX,
        }
    }

    /// `usual`, or rarely a count in `0..=most` (a wrong one).
    pub fn count_or(&mut self, usual: usize, most: u32) -> usize {
        if self.rare() {
            self.below(most + 1) as usize
        } else {
            usual
        }
    }

    /// An enum value in `0..n` (`n` of them valid), rarely any `u32`.
    pub fn choice(&mut self, n: u32) -> u32 {
        if self.rare() {
            self.u32()
        } else {
            self.below(n)
        }
    }

    /// A count in `0..=most`, rarely up to 255.
    pub fn count(&mut self, most: u32) -> usize {
        if self.rare() {
            usize::from(self.byte())
        } else {
            self.below(most + 1) as usize
        }
    }
}
