#include "smokescan/bag/mcap_writer.hpp"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>

#include "mcap_records.hpp"
#include "smokescan/core/error.hpp"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "MCAP's fields are written as this machine stores them");

namespace smokescan {

uint32_t mcap::crc32(uint32_t crc, const void* p, size_t n)
{
    return uint32_t(::crc32_z(crc, static_cast<const Bytef*>(p), n));
}

using mcap::Fields;

struct McapWriter::Impl {
    /// A written chunk's Chunk Index record's fields.
    struct ChunkIndexInfo {
        uint64_t start_ns, end_ns, offset, length, index_length, compressed, uncompressed;
        std::map<uint16_t, uint64_t> index_offsets;
    };
    std::ostream& out;
    McapWriterConfig cfg;
    uint64_t pos = 0;
    uint32_t data_crc = 0, summary_crc = 0;
    bool in_summary = false, finished = false;
    std::vector<std::vector<uint8_t>> schemas, channels;  ///< their records, for the summary
    std::vector<std::string> topics;  ///< by channel id − 1
    std::vector<uint32_t> sequence;  ///< by channel id − 1
    std::vector<uint8_t> chunk;  ///< the open chunk's records, uncompressed
    uint64_t chunk_start = 0, chunk_end = 0;
    bool chunk_has_messages = false;
    std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> index;  ///< the open chunk's (log time, offset)
    std::vector<ChunkIndexInfo> chunk_indexes;
    McapWriteResult result;
    std::map<uint16_t, uint64_t> per_channel;

    Impl(std::ostream& o, McapWriterConfig c) : out(o), cfg(std::move(c)) {}
    void emit(const void* p, size_t n)
    {
        out.write(static_cast<const char*>(p), std::streamsize(n));
        if (in_summary)
            summary_crc = mcap::crc32(summary_crc, p, n);
        else
            data_crc = mcap::crc32(data_crc, p, n);
        pos += n;
    }
    void emit(const std::vector<uint8_t>& r) { emit(r.data(), r.size()); }
    void toChunk(const std::vector<uint8_t>& r) { chunk.insert(chunk.end(), r.begin(), r.end()); }
    void flushChunk();
};

McapWriter::McapWriter(std::ostream& out, McapWriterConfig cfg) : impl_(new Impl(out, std::move(cfg)))
{
    impl_->emit(mcap::kMagic, sizeof mcap::kMagic);
    impl_->emit(Fields().str(impl_->cfg.profile).str("smokescan").record(mcap::kHeader));
}

McapWriter::~McapWriter() { delete impl_; }

uint16_t McapWriter::addSchema(const std::string& name, const std::string& encoding, const std::string& data)
{
    Impl& m = *impl_;
    if (m.schemas.size() >= 65535) throw Error("mcap", "more than 65535 schemas");
    const auto id = uint16_t(m.schemas.size() + 1);
    const std::vector<uint8_t> r = Fields()
                                       .num(id)
                                       .str(name)
                                       .str(encoding)
                                       .num(uint32_t(data.size()))
                                       .bytes(data.data(), data.size())
                                       .record(mcap::kSchema);
    m.schemas.push_back(r);
    m.toChunk(r);
    return id;
}

uint16_t McapWriter::addChannel(uint16_t schema, const std::string& topic, const std::string& message_encoding,
                                const std::map<std::string, std::string>& metadata)
{
    Impl& m = *impl_;
    if (m.channels.size() >= 65535) throw Error("mcap", "more than 65535 channels");
    if (schema == 0 || schema > m.schemas.size())
        throw Error("mcap", "channel " + topic + ": no schema " + std::to_string(schema));
    const auto id = uint16_t(m.channels.size() + 1);
    Fields meta;
    for (const auto& [k, v] : metadata) meta.str(k).str(v);
    const std::vector<uint8_t> r = Fields()
                                       .num(id)
                                       .num(schema)
                                       .str(topic)
                                       .str(message_encoding)
                                       .num(uint32_t(meta.content().size()))
                                       .bytes(meta.content().data(), meta.content().size())
                                       .record(mcap::kChannel);
    m.channels.push_back(r);
    m.topics.push_back(topic);
    m.sequence.push_back(0);
    m.toChunk(r);
    return id;
}

void McapWriter::write(uint16_t channel, uint64_t log_ns, uint64_t publish_ns, const std::vector<uint8_t>& data)
{
    Impl& m = *impl_;
    if (channel == 0 || channel > m.channels.size()) throw Error("mcap", "no channel " + std::to_string(channel));
    const uint32_t seq = m.sequence[channel - 1]++;
    m.index[channel].push_back({log_ns, uint64_t(m.chunk.size())});
    m.toChunk(Fields()
                  .num(channel)
                  .num(seq)
                  .num(log_ns)
                  .num(publish_ns)
                  .bytes(data.data(), data.size())
                  .record(mcap::kMessage));
    m.chunk_start = m.chunk_has_messages ? std::min(m.chunk_start, log_ns) : log_ns;
    m.chunk_end = m.chunk_has_messages ? std::max(m.chunk_end, log_ns) : log_ns;
    m.chunk_has_messages = true;
    McapWriteResult& r = m.result;
    r.start_ns = r.messages ? std::min(r.start_ns, log_ns) : log_ns;
    r.end_ns = r.messages ? std::max(r.end_ns, log_ns) : log_ns;
    ++r.messages;
    ++r.per_topic[m.topics[channel - 1]];
    ++m.per_channel[channel];
    if (m.chunk.size() >= m.cfg.chunk_bytes) m.flushChunk();
}

void McapWriter::Impl::flushChunk()
{
    if (chunk.empty()) return;
    std::vector<uint8_t> packed(ZSTD_compressBound(chunk.size()));
    const size_t n = ZSTD_compress(packed.data(), packed.size(), chunk.data(), chunk.size(), cfg.zstd_level);
    if (ZSTD_isError(n)) throw Error("mcap", std::string("zstd: ") + ZSTD_getErrorName(n));
    ChunkIndexInfo ci;
    ci.start_ns = chunk_has_messages ? chunk_start : 0;
    ci.end_ns = chunk_has_messages ? chunk_end : 0;
    ci.offset = pos;
    ci.compressed = n;
    ci.uncompressed = chunk.size();
    const std::vector<uint8_t> r = Fields()
                                       .num(ci.start_ns)
                                       .num(ci.end_ns)
                                       .num(uint64_t(chunk.size()))
                                       .num(mcap::crc32(0, chunk.data(), chunk.size()))
                                       .str("zstd")
                                       .num(uint64_t(n))
                                       .bytes(packed.data(), n)
                                       .record(mcap::kChunk);
    emit(r);
    ci.length = r.size();
    const uint64_t index_start = pos;
    for (const auto& [channel, entries] : index) {
        Fields f;
        f.num(channel).num(uint32_t(entries.size() * 16));
        for (const auto& [t, offset] : entries) f.num(t).num(offset);
        ci.index_offsets[channel] = pos;
        emit(f.record(mcap::kMessageIndex));
    }
    ci.index_length = pos - index_start;
    chunk_indexes.push_back(ci);
    chunk.clear();
    index.clear();
    chunk_has_messages = false;
    ++result.chunks;
}

McapWriteResult McapWriter::finish()
{
    Impl& m = *impl_;
    if (m.finished) throw Error("mcap", "finished twice");
    m.finished = true;
    m.flushChunk();
    const uint32_t crc = m.data_crc;
    m.emit(Fields().num(crc).record(mcap::kDataEnd));
    // The summary: each group of one opcode, then an offset record per group.
    const uint64_t summary_start = m.pos;
    m.in_summary = true;
    std::vector<std::vector<uint8_t>> offsets;
    auto group = [&](uint8_t op, const std::vector<std::vector<uint8_t>>& records) {
        if (records.empty()) return;
        const uint64_t start = m.pos;
        for (const auto& r : records) m.emit(r);
        offsets.push_back(Fields().num(op).num(start).num(m.pos - start).record(mcap::kSummaryOffset));
    };
    group(mcap::kSchema, m.schemas);
    group(mcap::kChannel, m.channels);
    Fields counts;
    for (const auto& [channel, n] : m.per_channel) counts.num(channel).num(n);
    const McapWriteResult& res = m.result;
    group(mcap::kStatistics,
          {Fields()
               .num(res.messages)
               .num(uint16_t(m.schemas.size()))
               .num(uint32_t(m.channels.size()))
               .num(uint32_t(0))
               .num(uint32_t(0))
               .num(uint32_t(m.chunk_indexes.size()))
               .num(res.start_ns)
               .num(res.end_ns)
               .num(uint32_t(counts.content().size()))
               .bytes(counts.content().data(), counts.content().size())
               .record(mcap::kStatistics)});
    std::vector<std::vector<uint8_t>> chunk_records;
    for (const Impl::ChunkIndexInfo& ci : m.chunk_indexes) {
        Fields map;
        for (const auto& [channel, offset] : ci.index_offsets) map.num(channel).num(offset);
        chunk_records.push_back(Fields()
                                    .num(ci.start_ns)
                                    .num(ci.end_ns)
                                    .num(ci.offset)
                                    .num(ci.length)
                                    .num(uint32_t(map.content().size()))
                                    .bytes(map.content().data(), map.content().size())
                                    .num(ci.index_length)
                                    .str("zstd")
                                    .num(ci.compressed)
                                    .num(ci.uncompressed)
                                    .record(mcap::kChunkIndex));
    }
    group(mcap::kChunkIndex, chunk_records);
    const uint64_t offsets_start = m.pos;
    for (const auto& r : offsets) m.emit(r);
    // The footer's CRC covers the summary up to its own summary_offset_start field.
    std::vector<uint8_t> footer = Fields().num(summary_start).num(offsets_start).record(mcap::kFooter);
    const uint64_t footer_len = 20;
    std::memcpy(footer.data() + 1, &footer_len, 8);
    m.emit(footer);
    const uint32_t summary_crc = m.summary_crc;
    m.in_summary = false;
    m.emit(&summary_crc, 4);
    m.emit(mcap::kMagic, sizeof mcap::kMagic);
    m.out.flush();
    if (!m.out) throw Error("mcap", "the file could not be written");
    m.result.bytes = m.pos;
    return m.result;
}

}  // namespace smokescan
