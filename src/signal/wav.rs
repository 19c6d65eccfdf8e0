//! Mono 16-bit PCM WAV export, so a simulated squeal can be listened to.
//!
//! File layout (canonical 44-byte RIFF header, little-endian): "RIFF", file size - 8, "WAVE";
//! "fmt " chunk of 16 bytes: format 1 (PCM), 1 channel, sample rate, byte rate = rate * 2,
//! block align 2, 16 bits per sample; "data" chunk: size, then the i16 samples.

use std::path::Path;

use super::resample::resample;
use crate::{Error, Result};

/// Peak level of the written audio as a fraction of full scale (headroom for players).
pub const PEAK_FRACTION_OF_FULL_SCALE: f64 = 0.9;

/// Default audio sample rate (Hz): the CD rate, which every player plays.
pub const DEFAULT_SAMPLE_RATE_HZ: u32 = 44_100;

/// Audio sample rates accepted (Hz): 8 kHz (telephone) to 384 kHz (the highest rate common
/// audio interfaces play); beyond, the resampled file only grows.
pub const SAMPLE_RATE_RANGE_HZ: (u32, u32) = (8_000, 384_000);

/// Converts a signal to 16-bit audio at `output_rate_hz`: resampled (windowed sinc, see
/// [`resample`]), mean removed (a displacement's static offset is inaudible but would eat
/// headroom), scaled so the largest magnitude is [`PEAK_FRACTION_OF_FULL_SCALE`] of 32767.
/// An all-constant signal gives silence.
pub fn to_pcm16(signal: &[f64], input_rate_hz: f64, output_rate_hz: f64) -> Result<Vec<i16>> {
    if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(
            "wav",
            "signal",
            format!("sample {index} is not finite"),
        ));
    }
    let mut audio = resample(signal, input_rate_hz, output_rate_hz)?;
    let mean = audio.iter().sum::<f64>() / audio.len() as f64;
    let peak = audio.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
    let gain = if peak > 0.0 {
        PEAK_FRACTION_OF_FULL_SCALE * i16::MAX as f64 / peak
    } else {
        0.0
    };
    for value in audio.iter_mut() {
        *value = ((*value - mean) * gain).round();
    }
    Ok(audio
        .into_iter()
        .map(|v| v.clamp(i16::MIN as f64, i16::MAX as f64) as i16)
        .collect())
}

/// Bytes of a mono 16-bit PCM WAV file (module documentation).
pub fn encode_pcm16_wav(samples: &[i16], sample_rate_hz: u32) -> Vec<u8> {
    let data_bytes = (samples.len() * 2) as u32;
    let mut bytes = Vec::with_capacity(44 + samples.len() * 2);
    bytes.extend_from_slice(b"RIFF");
    bytes.extend_from_slice(&(36 + data_bytes).to_le_bytes());
    bytes.extend_from_slice(b"WAVE");
    bytes.extend_from_slice(b"fmt ");
    bytes.extend_from_slice(&16u32.to_le_bytes());
    bytes.extend_from_slice(&1u16.to_le_bytes()); // PCM
    bytes.extend_from_slice(&1u16.to_le_bytes()); // mono
    bytes.extend_from_slice(&sample_rate_hz.to_le_bytes());
    bytes.extend_from_slice(&(sample_rate_hz * 2).to_le_bytes()); // byte rate
    bytes.extend_from_slice(&2u16.to_le_bytes()); // block align
    bytes.extend_from_slice(&16u16.to_le_bytes()); // bits per sample
    bytes.extend_from_slice(b"data");
    bytes.extend_from_slice(&data_bytes.to_le_bytes());
    for sample in samples {
        bytes.extend_from_slice(&sample.to_le_bytes());
    }
    bytes
}

/// Writes `signal` (sampled at `input_rate_hz`) as a WAV file at `output_rate_hz`; returns
/// the number of audio samples written.
pub fn write_wav(
    path: &Path,
    signal: &[f64],
    input_rate_hz: f64,
    output_rate_hz: u32,
) -> Result<usize> {
    let (lo, hi) = SAMPLE_RATE_RANGE_HZ;
    if !(lo..=hi).contains(&output_rate_hz) {
        return Err(Error::input(
            "wav",
            "--sample-rate-hz",
            format!(
                "must be in [{lo}, {hi}] Hz (e.g. {DEFAULT_SAMPLE_RATE_HZ}), got {output_rate_hz}"
            ),
        ));
    }
    let samples = to_pcm16(signal, input_rate_hz, output_rate_hz as f64)?;
    if samples.len() * 2 > (u32::MAX - 36) as usize {
        return Err(Error::input(
            "wav",
            "signal",
            "audio longer than a WAV file can hold (4 GiB)",
        ));
    }
    std::fs::write(path, encode_pcm16_wav(&samples, output_rate_hz))
        .map_err(|e| Error::io(path, e))?;
    Ok(samples.len())
}

/// A decoded mono 16-bit PCM WAV file.
#[derive(Debug, Clone, PartialEq)]
pub struct Pcm16Wav {
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Samples.
    pub samples: Vec<i16>,
}

/// Reads a canonical mono 16-bit PCM WAV file (as written by [`write_wav`]); anything else
/// is an input error naming what differs.
pub fn read_pcm16_wav(path: &Path) -> Result<Pcm16Wav> {
    let bytes = std::fs::read(path).map_err(|e| Error::reading(path, e))?;
    let source = path.display().to_string();
    let bad = |field: &str, message: String| Error::input(source.clone(), field, message);
    if bytes.len() < 44
        || &bytes[0..4] != b"RIFF"
        || &bytes[8..12] != b"WAVE"
        || &bytes[12..16] != b"fmt "
    {
        return Err(bad("header", "not a canonical RIFF/WAVE file".into()));
    }
    let u16_at = |i: usize| u16::from_le_bytes([bytes[i], bytes[i + 1]]);
    let u32_at =
        |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    if u32_at(4) as usize != bytes.len() - 8 {
        return Err(bad(
            "riff_size",
            format!("{} but the file has {} bytes", u32_at(4), bytes.len()),
        ));
    }
    if u32_at(16) != 16 || u16_at(20) != 1 || u16_at(22) != 1 || u16_at(34) != 16 {
        return Err(bad("fmt", "only mono 16-bit PCM is supported".into()));
    }
    let sample_rate_hz = u32_at(24);
    if u32_at(28) != sample_rate_hz * 2 || u16_at(32) != 2 {
        return Err(bad(
            "fmt",
            "byte rate / block align inconsistent with mono 16-bit".into(),
        ));
    }
    if &bytes[36..40] != b"data" || u32_at(40) as usize != bytes.len() - 44 {
        return Err(bad(
            "data",
            "data chunk size does not match the file".into(),
        ));
    }
    let samples = bytes[44..]
        .chunks_exact(2)
        .map(|b| i16::from_le_bytes([b[0], b[1]]))
        .collect();
    Ok(Pcm16Wav {
        sample_rate_hz,
        samples,
    })
}
